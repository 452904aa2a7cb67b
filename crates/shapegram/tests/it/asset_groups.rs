//! An OBJ asset's `g` groups and `usemtl` materials, read from a file through `shapegram
//! derive`, as `comp(g)`, `comp(m)`, `geometry.groups` and `geometry.materials` see them.

use crate::common;

use common::{TempDir, shapegram, stderr};

/// A pane (1 × 1 at z = 0) in group `glass` and a frame plate behind it (at z = −1) in group
/// `frame`, both wearing material `metal`.
const PANE_OBJ: &str = "mtllib pane.mtl
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0 0 -1
v 0 1 -1
v 1 1 -1
v 1 0 -1
usemtl metal
g glass
f 1 2 3 4
g frame
f 5 6 7 8
";

#[test]
fn groups_and_materials_of_an_obj_asset() {
    let dir = TempDir::new("asset-groups");
    std::fs::write(dir.path("pane.obj"), PANE_OBJ).unwrap();
    std::fs::write(dir.path("pane.mtl"), "newmtl metal\nKd 0.5 0.5 0.5\n").unwrap();
    let grammar = dir.path("pane.cga");
    std::fs::write(
        &grammar,
        "Lot --> s(4, 2, 1) i(\"pane.obj\")
                 report(\"groups\", size(geometry.groups))
                 report(\"materials\", size(geometry.materials))
                 comp(g) { findFirst(geometry.groups, \"frame\") >= 0 : Frame | all : Glass }
         Frame --> report(\"frame\", geometry.area)
         Glass --> report(\"glass\", geometry.area)\n",
    )
    .unwrap();
    let output = shapegram(&["derive".as_ref(), grammar.as_os_str(), "--stats".as_ref()]);
    assert!(output.status.success(), "{}", stderr(&output));
    let stats: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
    let reports = &stats["reports"];
    assert_eq!(reports["groups"]["sum"], 2.0);
    assert_eq!(reports["materials"]["sum"], 1.0);
    assert_eq!(reports["frame"]["count"], 1);
    assert_eq!(reports["frame"]["sum"], 8.0);
    assert_eq!(reports["glass"]["count"], 1);
    assert_eq!(reports["glass"]["sum"], 8.0);
}

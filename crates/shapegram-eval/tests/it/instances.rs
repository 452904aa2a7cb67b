//! `Derivation::to_model_with`: which leaves become instances of a prototype, and the
//! metadata each leaf carries.

use crate::common;

use common::*;
use shapegram_eval::{DeriveOptions, InstanceCandidates, MetadataScope, ModelOptions, derive};
use shapegram_geom::{DVec3, MetaValue};

fn instances(candidates: InstanceCandidates) -> ModelOptions {
    ModelOptions {
        instances: candidates,
        ..ModelOptions::default()
    }
}

/// The prototype of each part (`None`: not an instance), in part order.
fn prototypes(text: &str, candidates: InstanceCandidates) -> Vec<(String, Option<u32>)> {
    let model = run(text, lot(20.0, 10.0)).to_model_with(&instances(candidates));
    model
        .parts
        .iter()
        .map(|p| (p.name.clone(), p.instance.map(|i| i.prototype)))
        .collect()
}

#[test]
fn copies_of_an_asset_share_a_prototype_whatever_their_size() {
    // Four posts of two heights and two turns, and one cut in two.
    let parts = prototypes(
        r#"Lot --> split(x) { '0.2 : Post(split.index) }*
           Post(i) --> s('0.5, 2 + i % 2, '0.5) r(0, 90 * (i % 2), 0) i("builtin:cylinder") Cut(i)
           Cut(i) --> case i == 4 : split(y) { 1 : Low. | ~1 : High. }
                      else : Whole."#,
        InstanceCandidates::Meshes,
    );
    assert_eq!(
        parts,
        [
            ("Whole".to_owned(), Some(0)),
            ("Whole".to_owned(), Some(0)),
            ("Whole".to_owned(), Some(0)),
            ("Whole".to_owned(), Some(0)),
            // Each half is used once: nothing to share.
            ("Low".to_owned(), None),
            ("High".to_owned(), None),
        ]
    );
}

#[test]
fn the_transform_places_the_prototype_where_the_leaf_is() {
    let derivation = run(
        r#"Lot --> split(x) { '0.5 : s(2, 3, 4) t(1, 0, 1) r(0, 30, 0) i("builtin:cone") Cone. }*"#,
        lot(20.0, 10.0),
    );
    let model = derivation.to_model_with(&instances(InstanceCandidates::Meshes));
    assert_eq!(model.parts.len(), 2);
    let first = &model.parts[0];
    let instance = first.instance.unwrap();
    // The prototype's geometry is the first copy's, moved back into the unit box.
    let local = first.mesh.transformed(&instance.transform.inverse());
    let bounds = local.bounds().unwrap();
    assert!(bounds.min.abs_diff_eq(DVec3::ZERO, 1e-9), "{bounds:?}");
    assert!(bounds.max.abs_diff_eq(DVec3::ONE, 1e-9), "{bounds:?}");
    let second = &model.parts[1];
    let moved = local.transformed(&second.instance.unwrap().transform);
    for (a, b) in moved.positions().iter().zip(second.mesh.positions()) {
        assert!(a.abs_diff_eq(*b, 1e-9), "{a} against {b}");
    }
    let scale = instance.transform.to_scale_rotation_translation().0;
    assert!(
        scale.abs_diff_eq(DVec3::new(2.0, 3.0, 4.0), 1e-9),
        "{scale}"
    );
}

#[test]
fn boxes_are_instances_only_when_asked() {
    let text = r#"Lot --> split(x) { '0.25 : s('0.5, 3, '0.5) primitiveCube() Block. }*"#;
    let none: Vec<_> = prototypes(text, InstanceCandidates::Meshes);
    assert_eq!(none, [("Block".to_owned(), None)], "merged into one part");
    let all = prototypes(text, InstanceCandidates::All);
    assert_eq!(all.len(), 4);
    assert!(all.iter().all(|(_, p)| *p == Some(0)));
    assert!(prototypes(text, InstanceCandidates::None).len() == 1);
}

#[test]
fn skinned_leaves_are_never_instances() {
    let parts = prototypes(
        r#"Lot --> joint(0, 0, 0) split(x) { '0.25 : s('0.5, 2, '0.5) i("builtin:cylinder") Post. }*"#,
        InstanceCandidates::All,
    );
    assert!(!parts.is_empty());
    assert!(parts.iter().all(|(_, p)| p.is_none()), "{parts:?}");
}

#[test]
fn leaves_carry_rule_path_and_attributes() {
    let program = compile(
        r#"attr height = 3
           attr label = "post"
           Lot --> split(x) { '0.5 : Post }*
           Post --> set(height, 5) s('0.5, height, '0.5) Pole."#,
    );
    let options = DeriveOptions {
        keep_tree: true,
        ..DeriveOptions::default()
    };
    let derivation = derive(&program, &[lot(20.0, 10.0)], &options).unwrap();
    let model = derivation.to_model_with(&ModelOptions {
        metadata: MetadataScope::Leaf,
        attr_names: program.attr_names().map(str::to_owned).collect(),
        ..ModelOptions::default()
    });
    assert_eq!(model.parts.len(), 2, "a part per leaf");
    let meta = model.parts[1].metadata.as_deref().unwrap();
    assert_eq!(meta.rule.as_deref(), Some("Pole"));
    assert_eq!(meta.path.as_deref(), Some("Lot[0]/Lot[1]/Post[0]/Pole[0]"));
    assert_eq!(
        meta.attributes,
        [
            ("height".to_owned(), MetaValue::Number(5.0)),
            ("label".to_owned(), MetaValue::Text("post".to_owned())),
        ]
    );
    // Without the tree there is no path to tell.
    let bare = run("Lot --> Pole.", lot(4.0, 4.0)).to_model_with(&ModelOptions {
        metadata: MetadataScope::Leaf,
        ..ModelOptions::default()
    });
    let meta = bare.parts[0].metadata.as_deref().unwrap();
    assert_eq!(
        (meta.rule.as_deref(), meta.path.as_deref()),
        (Some("Pole"), None)
    );
}

#[test]
fn parts_carry_their_rule_leaf_count_and_shared_attributes() {
    let program = compile(
        r##"attr height = 3
           attr label = "post"
           Lot --> split(x) { '0.25 : Post(split.index) }*
           Post(i) --> case i < 3 : set(height, 4 + i % 2) Pole.
                       else : color("#ff0000") Pole."##,
    );
    let options = DeriveOptions {
        keep_tree: true,
        ..DeriveOptions::default()
    };
    let derivation = derive(&program, &[lot(20.0, 10.0)], &options).unwrap();
    let model = derivation.to_model_with(&ModelOptions {
        metadata: MetadataScope::Part,
        attr_names: program.attr_names().map(str::to_owned).collect(),
        ..ModelOptions::default()
    });
    // Three grey poles of heights 4, 5, 4 and a red one: a part per colour, as without metadata.
    assert_eq!(model.parts.len(), 2);
    let grey = model.parts[0].metadata.as_deref().unwrap();
    assert_eq!(grey.rule.as_deref(), Some("Pole"));
    assert_eq!(grey.leaves, Some(3));
    assert_eq!(grey.path, None);
    assert_eq!(
        grey.attributes,
        [("label".to_owned(), MetaValue::Text("post".to_owned()))],
        "the heights differ"
    );
    let red = model.parts[1].metadata.as_deref().unwrap();
    assert_eq!(red.leaves, Some(1));
    assert_eq!(red.attributes.len(), 2);
}

#[test]
fn only_sharing_that_saves_bytes_changes_the_model_when_asked() {
    let smaller = ModelOptions {
        instances: InstanceCandidates::All,
        smaller_only: true,
        ..ModelOptions::default()
    };
    // Four quads of the lot: cheaper written than shared, so the model is the plain one.
    let tiles = run("Lot --> split(x) { '0.25 : Tile. }*", lot(20.0, 10.0));
    assert_eq!(tiles.to_model_with(&smaller), tiles.to_model());
    assert_eq!(
        tiles
            .to_model_with(&instances(InstanceCandidates::All))
            .parts
            .len(),
        4,
        "without the byte test every quad is an instance"
    );
    // Forty spheres are worth sharing.
    let balls = run(
        r#"Lot --> split(x) { '0.025 : s('0.5, 1, '0.5) i("builtin:sphere") Ball. }*"#,
        lot(40.0, 10.0),
    );
    let model = balls.to_model_with(&smaller);
    assert_eq!(model.parts.len(), 40);
    assert!(
        model
            .parts
            .iter()
            .all(|p| p.instance.map(|i| i.prototype) == Some(0))
    );
}

//! The studio's attributes, seed, lots, exports and cancelled derivations, end to end against
//! `shapegram studio` with the engine of `shapegram derive`: the models must be the bytes
//! `derive` writes for the same attributes, seed and lot.

use std::time::{Duration, Instant};

use crate::common;
use crate::studio_child::{self, Studio};

use base64::Engine as _;
use common::{TempDir, shapegram};
use serde_json::{Value, json};

fn start(file: &std::path::Path, timeout: &str) -> Studio {
    studio_child::start(&[file.as_os_str(), "--timeout".as_ref(), timeout.as_ref()])
}

/// A POST from the studio's page: the status and JSON body.
fn post(addr: &str, path: &str, body: &Value) -> (u16, Value) {
    studio_child::send(addr, "POST", path, Some(body))
}

fn base64(text: &Value) -> Vec<u8> {
    base64::engine::general_purpose::STANDARD
        .decode(text.as_str().unwrap())
        .unwrap()
}

/// What `shapegram derive` writes for `args` into `output`.
fn derived(args: &[&str], output: &std::path::Path) -> Vec<u8> {
    let out = shapegram(&[args, &["-q", "-o", output.to_str().unwrap()]].concat());
    assert!(out.status.success(), "{}", common::stderr(&out));
    std::fs::read(output).unwrap()
}

const TOWER: &str = "\
@Group(\"Mass\", 1) @Order(2) @Range(min=5, max=40, stepsize=1)
@Description(\"Height in metres\")
attr height = 10
@Group(\"Mass\", 1) @Order(1) @Enum(\"flat\", \"hip\")
attr roof = \"flat\"
@Color
attr wall = \"#c0b090\"
@Hidden
attr secret = height * 2
attr lit = true

@StartRule
Lot --> extrude(height) color(wall) Mass
Mass --> case roof == \"hip\" : comp(f) { top : roofHip(30) Roof. | all : Wall. }
         else : comp(f) { all : Wall. }
";

#[test]
fn attributes_come_with_their_annotations_and_override_the_defaults_as_attr_does() {
    let dir = TempDir::new("studio-attrs");
    let file = dir.path("tower.cga");
    std::fs::write(&file, TOWER).unwrap();
    let file = std::fs::canonicalize(&file).unwrap();
    let studio = start(&file, "10");
    let ask = |extra: Value| {
        let mut body = json!({"path": file, "text": TOWER});
        body.as_object_mut()
            .unwrap()
            .extend(extra.as_object().unwrap().clone());
        post(&studio.addr, "/api/derive", &body)
    };
    let (status, plain) = ask(json!({}));
    assert_eq!(status, 200, "{plain}");
    assert_eq!(
        plain["attrs"][0],
        json!({
            "name": "height", "type": "number", "default": 10.0, "value": 10.0, "user": false,
            "range": {"min": 5.0, "max": 40.0, "step": 1.0}, "restricted": true, "color": false,
            "group": ["Mass"], "group_order": 1.0, "order": 2.0, "hidden": false,
            "description": "Height in metres",
            "annotations": ["Group", "Order", "Range", "Description"],
        })
    );
    assert_eq!(plain["attrs"][1]["choices"], json!(["flat", "hip"]));
    assert_eq!(plain["attrs"][2]["color"], json!(true));
    assert_eq!(
        (&plain["attrs"][3]["hidden"], &plain["attrs"][3]["value"]),
        (&json!(true), &json!(20.0))
    );
    assert_eq!(plain["attrs"][4]["type"], json!("boolean"));

    // The user's values and seed: the GLB `derive --attr … --seed …` writes, byte for byte.
    let (status, set) = ask(json!({"seed": 7, "attrs": {"height": 23, "roof": "hip"}}));
    assert_eq!(status, 200, "{set}");
    let expected = derived(
        &[
            "derive",
            file.to_str().unwrap(),
            "--seed",
            "7",
            "--attr",
            "height=23",
            "--attr",
            "roof=hip",
        ],
        &dir.path("set.glb"),
    );
    assert_eq!(base64(&set["glb"]), expected);
    assert_ne!(base64(&set["glb"]), base64(&plain["glb"]));
    let height = &set["attrs"][0];
    assert_eq!(
        (&height["value"], &height["default"], &height["user"]),
        (&json!(23.0), &json!(10.0), &json!(true))
    );
    // The hidden attribute's default follows the user's height.
    assert_eq!(set["attrs"][3]["value"], json!(46.0));

    // Values that no longer fit are dropped with a note; the rest still counts.
    let (status, stale) = ask(json!({"attrs": {"height": 23, "roof": 3, "floors": 4}}));
    assert_eq!(status, 200, "{stale}");
    assert_eq!(stale["ok"], json!(true));
    assert_eq!(stale["dropped"], json!(["floors", "roof"]));
    assert_eq!(
        stale["notes"],
        json!([
            "`floors` is no longer an attribute of the grammar: its value was dropped",
            "`roof` is now a string: the value 3 was dropped",
        ])
    );
    assert_eq!(stale["attrs"][0]["value"], json!(23.0));
}

#[test]
fn lots_are_drawn_or_read_from_files_as_derive_reads_them() {
    let dir = TempDir::new("studio-lots");
    let file = dir.path("tower.cga");
    std::fs::write(&file, TOWER).unwrap();
    let file = std::fs::canonicalize(&file).unwrap();
    let studio = start(&file, "10");
    let ask = |lot: Value| {
        post(
            &studio.addr,
            "/api/derive",
            &json!({"path": file, "text": TOWER, "lot": lot}),
        )
    };

    let (status, drawn) =
        ask(json!({"kind": "polygon", "points": [[0, 0], [12, 0], [12, 9], [0, 9]]}));
    assert_eq!(status, 200, "{drawn}");
    let expected = derived(
        &[
            "derive",
            file.to_str().unwrap(),
            "--lot",
            "0,0 12,0 12,9 0,9",
        ],
        &dir.path("drawn.glb"),
    );
    assert_eq!(base64(&drawn["glb"]), expected);
    assert_eq!(drawn["lots"], json!(1));

    let geojson = r#"{"type": "FeatureCollection", "features": [
        {"type": "Feature", "geometry": {"type": "Polygon", "coordinates": [[[0, 0], [10, 0], [10, 5], [0, 5], [0, 0]]]}},
        {"type": "Feature", "geometry": {"type": "Polygon", "coordinates": [[[20, 0], [30, 0], [25, 8], [20, 0]]]}},
        {"type": "Feature", "geometry": {"type": "Point", "coordinates": [1, 2]}}]}"#;
    std::fs::write(dir.path("lots.geojson"), geojson).unwrap();
    let (status, city) = ask(json!({"kind": "file", "name": "lots.geojson", "text": geojson}));
    assert_eq!(status, 200, "{city}");
    let expected = derived(
        &[
            "derive",
            file.to_str().unwrap(),
            "--lots",
            dir.path("lots.geojson").to_str().unwrap(),
        ],
        &dir.path("city.glb"),
    );
    assert_eq!(base64(&city["glb"]), expected);
    assert_eq!(city["lots"], json!(2));
    assert_eq!(
        city["notes"],
        json!(["lots.geojson: skipped 1 geometry that is not polygons"])
    );

    // Bad lots: a clear message, no model, and still 200 (the text may be fine).
    for (lot, message) in [
        (
            json!({"kind": "polygon", "points": [[0, 0], [5, 0], [10, 0]]}),
            "the drawn lot has no area (its corners are on one line or on one point)",
        ),
        (
            json!({"kind": "file", "name": "lots.geojson", "text": "{\"type\": \"Circle\"}"}),
            "invalid GeoJSON in lots.geojson: the top level has the unknown type \"Circle\"",
        ),
        (
            json!({"kind": "file", "name": "lots.obj", "text": "v 0 0 0\n"}),
            "lots.obj has no polygons to use as lots",
        ),
    ] {
        let (status, bad) = ask(lot);
        assert_eq!(status, 200, "{bad}");
        assert_eq!(bad["ok"], json!(false));
        assert!(bad["error"].as_str().unwrap().starts_with(message), "{bad}");
    }
    let (status, refused) = ask(json!({"kind": "circle", "radius": 3}));
    assert_eq!(status, 400, "{refused}");
}

#[test]
fn exports_are_the_files_derive_writes() {
    let dir = TempDir::new("studio-export");
    let file = dir.path("tower.cga");
    std::fs::write(&file, TOWER).unwrap();
    let file = std::fs::canonicalize(&file).unwrap();
    let studio = start(&file, "10");
    let export = |format: &str| {
        post(
            &studio.addr,
            "/api/export",
            &json!({"path": file, "text": TOWER, "seed": 3, "attrs": {"roof": "hip"},
                    "lot": {"kind": "polygon", "points": [[0, 0], [8, 0], [8, 6], [0, 6]]},
                    "format": format}),
        )
    };
    let cli = dir.path("cli");
    std::fs::create_dir(&cli).unwrap();
    for (format, names) in [
        ("glb", vec!["tower.glb"]),
        ("stl", vec!["tower.stl"]),
        ("obj", vec!["tower.obj", "tower.mtl"]),
    ] {
        // `derive -o tower.obj` writes tower.mtl beside it.
        derived(
            &[
                "derive",
                file.to_str().unwrap(),
                "--seed",
                "3",
                "--attr",
                "roof=hip",
                "--lot",
                "0,0 8,0 8,6 0,6",
            ],
            &cli.join(names[0]),
        );
        let (status, answer) = export(format);
        assert_eq!(status, 200, "{answer}");
        let files = answer["files"].as_array().unwrap();
        let got: Vec<&str> = files.iter().map(|f| f["name"].as_str().unwrap()).collect();
        assert_eq!(got, names);
        for f in files {
            let bytes = base64(&f["data"]);
            assert_eq!(f["bytes"], json!(bytes.len()));
            let name = f["name"].as_str().unwrap();
            assert_eq!(bytes, std::fs::read(cli.join(name)).unwrap(), "{name}");
        }
    }
    let (status, broken) = post(
        &studio.addr,
        "/api/export",
        &json!({"path": file, "text": "Lot --> extrude(", "format": "stl"}),
    );
    assert_eq!(status, 422, "{broken}");
    assert!(
        broken["error"].as_str().unwrap().starts_with("1:17: "),
        "{broken}"
    );
}

/// A grammar that takes seconds: a binary split 20 levels deep (2 million shapes), every shape
/// deleted.
const SLOW: &str = "\
Lot --> A(0)
A(d) --> case d < 20 : split(x) { '0.5 : A(d + 1) | '0.5 : A(d + 1) }
         else : NIL
";

#[test]
fn a_newer_request_cancels_the_running_derivation() {
    newer_request_cancels("slow.cga", SLOW, "Lot --> extrude(3) X.");
}

/// Caves are cancelled while they are meshed: a sphere at 32 cells per metre.
#[test]
fn a_newer_request_cancels_the_running_cave() {
    newer_request_cancels(
        "slow.cave",
        "lod 32\nadd sphere(5)\n",
        "lod 2\nadd box(1, 1, 1)\n",
    );
}

/// `slow` in the file `name` takes a while alone; sent again and followed by `quick` a fifth of
/// that time later, it is answered 409 and `quick` answered, both long before `slow` would have
/// ended. The times are relative to the one measured, so a faster engine or a busier machine
/// changes them all alike.
fn newer_request_cancels(name: &str, slow: &str, quick: &str) {
    let dir = TempDir::new("studio-cancel");
    let file = dir.path(name);
    std::fs::write(&file, slow).unwrap();
    let file = std::fs::canonicalize(&file).unwrap();
    let studio = start(&file, "120");
    let slow = json!({"path": file, "text": slow});
    let started = Instant::now();
    let (status, alone) = post(&studio.addr, "/api/derive", &slow);
    let alone_time = started.elapsed();
    assert_eq!((status, &alone["ok"]), (200, &json!(true)), "{alone}");
    assert!(
        alone_time > Duration::from_millis(200),
        "{name} is too quick to be cancelled: {alone_time:?}"
    );
    let delay = alone_time / 5;

    let addr = studio.addr.clone();
    let first = std::thread::spawn(move || {
        let started = Instant::now();
        let answer = post(&addr, "/api/derive", &slow);
        (answer, started.elapsed())
    });
    std::thread::sleep(delay);
    let started = Instant::now();
    let (status, second) = post(
        &studio.addr,
        "/api/derive",
        &json!({"path": file, "text": quick}),
    );
    let second_time = started.elapsed();
    assert_eq!((status, &second["ok"]), (200, &json!(true)), "{second}");
    let ((status, answer), first_time) = first.join().unwrap();
    assert_eq!(status, 409, "{answer}");
    assert!(
        answer["error"].as_str().unwrap().contains("was superseded"),
        "{answer}"
    );
    eprintln!(
        "{name} alone: {alone_time:?}; cancelled after {delay:?}: 409 after {first_time:?}, \
         the newer request answered in {second_time:?}"
    );
    // Both answered long before the first derivation would have ended.
    assert!(
        second_time * 3 < alone_time,
        "{second_time:?} against {alone_time:?}"
    );
    assert!(
        first_time * 2 < alone_time,
        "{first_time:?} against {alone_time:?}"
    );
}

//! End to end: `shapegram studio` as a child process on a free port, over real HTTP, with the
//! engine of `shapegram derive`: the address on the first line, models and counts as `derive`
//! makes them, diagnostics with their lines and columns, assets found beside the file.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::process::{Child, Command, Stdio};

mod common;

use common::{TempDir, example, shapegram, stderr};
use serde_json::{Value, json};

/// A `shapegram studio` child, killed on drop.
struct Studio {
    child: Child,
    /// `127.0.0.1:PORT`.
    addr: String,
}

impl Drop for Studio {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn start(files: &[&std::path::Path]) -> Studio {
    let mut child = Command::new(env!("CARGO_BIN_EXE_shapegram"))
        .arg("studio")
        .args(files)
        .args(["--listen", "127.0.0.1:0"])
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .spawn()
        .unwrap();
    let mut line = String::new();
    BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut line)
        .unwrap();
    let addr = line
        .strip_prefix("shapegram studio: http://")
        .and_then(|rest| rest.strip_suffix("/\n"))
        .unwrap_or_else(|| panic!("first line: {line:?}"))
        .to_owned();
    Studio { child, addr }
}

/// A request from the studio's page: the status and JSON body.
fn request(studio: &Studio, method: &str, path: &str, body: Option<Value>) -> (u16, Value) {
    let mut stream = TcpStream::connect(&studio.addr).unwrap();
    let body = body.map(|b| b.to_string()).unwrap_or_default();
    write!(
        stream,
        "{method} {path} HTTP/1.1\r\nHost: {addr}\r\nOrigin: http://{addr}\r\nConnection: close\r\nContent-Type: application/json\r\nContent-Length: {}\r\n\r\n{body}",
        body.len(),
        addr = studio.addr,
    )
    .unwrap();
    let mut answer = String::new();
    stream.read_to_string(&mut answer).unwrap();
    let status: u16 = answer[9..12].parse().unwrap();
    let (_, content) = answer.split_once("\r\n\r\n").unwrap();
    (status, serde_json::from_str(content).unwrap())
}

fn derive(studio: &Studio, path: &std::path::Path, text: &str) -> Value {
    let (status, answer) = request(
        studio,
        "POST",
        "/api/derive",
        Some(json!({"path": path, "text": text})),
    );
    assert_eq!(status, 200, "{answer}");
    answer
}

#[test]
fn the_studio_derives_text_as_derive_does_the_file() {
    let dir = TempDir::new("studio-derive");
    let house = dir.path("house.cga");
    std::fs::copy(example("house.cga"), &house).unwrap();
    let house = std::fs::canonicalize(&house).unwrap();
    let studio = start(&[&house]);
    let text = std::fs::read_to_string(&house).unwrap();
    let answer = derive(&studio, &house, &text);
    let stats = shapegram(&["derive", "-q", "--stats", house.to_str().unwrap()]);
    let stats: Value = serde_json::from_slice(&stats.stdout).unwrap();
    assert_eq!(
        (&answer["ok"], &answer["shapes"], &answer["leaves"]),
        (&json!(true), &stats["shapes"], &stats["leaves"])
    );
    assert_eq!(answer["diagnostics"], json!([]));
    // base64 of the GLB header's first six bytes: `glTF`, then version 2 (as u32 LE).
    assert!(answer["glb"].as_str().unwrap().starts_with("Z2xURgIA"));
    // The text, not the file: a third storey adds shapes; the file stays as it was.
    let taller = derive(
        &studio,
        &house,
        &text.replace("attr storeys    = 2", "attr storeys    = 3"),
    );
    assert!(taller["shapes"].as_u64() > answer["shapes"].as_u64());
    assert_eq!(std::fs::read_to_string(&house).unwrap(), text);
}

#[test]
fn diagnostics_come_with_lines_and_columns() {
    let dir = TempDir::new("studio-diagnostics");
    let file = dir.path("lot.cga");
    std::fs::write(&file, "Lot --> X.\n").unwrap();
    let file = std::fs::canonicalize(&file).unwrap();
    let studio = start(&[&file]);
    // A parse error.
    let answer = derive(&studio, &file, "// first\nLot --> extrude(3 Foo) X.\n");
    assert_eq!(answer["ok"], false);
    assert_eq!(answer["glb"], Value::Null);
    assert_eq!(
        answer["diagnostics"],
        json!([{
            "severity": "error",
            "message": "expected `,` or `)` in the argument list, found `Foo`",
            "label": "expected `,` or `)` here",
            "hints": [],
            "line": 2, "column": 19, "end_line": 2, "end_column": 22,
        }])
    );
    // An error while deriving, at its operation: an asset that is not beside the file.
    let answer = derive(&studio, &file, "Lot -->\n    i(\"missing.obj\")\n");
    let diagnostics = answer["diagnostics"].as_array().unwrap();
    assert_eq!(diagnostics.len(), 1, "{answer}");
    let missing = &diagnostics[0];
    assert_eq!(
        (
            &missing["severity"],
            &missing["line"],
            &missing["column"],
            &missing["end_line"],
            &missing["end_column"]
        ),
        (&json!("error"), &json!(2), &json!(7), &json!(2), &json!(20))
    );
    assert!(
        missing["message"]
            .as_str()
            .unwrap()
            .starts_with("cannot insert `missing.obj`: cannot read "),
        "{missing}"
    );
    // Once it is there, it is found beside the file.
    std::fs::copy(example("roof.obj"), dir.path("missing.obj")).unwrap();
    let answer = derive(&studio, &file, "Lot -->\n    i(\"missing.obj\")\n");
    assert_eq!(
        (&answer["ok"], &answer["diagnostics"]),
        (&json!(true), &json!([]))
    );
}

#[test]
fn the_studio_listens_on_loopback_only() {
    let output = shapegram(&[
        "studio",
        "--listen",
        "0.0.0.0:0",
        example("house.cga").to_str().unwrap(),
    ]);
    assert_eq!(output.status.code(), Some(1));
    assert_eq!(
        stderr(&output),
        "error: --listen 0.0.0.0:0: the studio listens on a loopback address only (127.0.0.1), since it writes your files\n"
    );
    let dir = TempDir::new("studio-not-grammar");
    let notes = dir.path("notes.txt");
    std::fs::write(&notes, "not a grammar").unwrap();
    let output = shapegram(&["studio", "--listen", "127.0.0.1:0", notes.to_str().unwrap()]);
    assert_eq!(output.status.code(), Some(1));
    assert_eq!(
        stderr(&output),
        format!(
            "error: {} is not a grammar file (.cga, .mul, .sgl, .goal, .lsys, .cave, .grammar)\n",
            notes.display()
        )
    );
}

/// The model or drawing of an answer, decoded.
fn glb_of(answer: &Value) -> Vec<u8> {
    use base64::Engine as _;
    let glb = answer["glb"]
        .as_str()
        .unwrap_or_else(|| panic!("no GLB: {answer}"));
    base64::engine::general_purpose::STANDARD
        .decode(glb)
        .unwrap()
}

/// Every kind of grammar derives in the studio as its command derives the file: a 2D L-system
/// as the SVG of `shapegram lsystem -o x.svg`, a 3D one, a cave and a topological grammar as
/// the GLB their commands write (byte for byte), and a goal grammar with its folder as library
/// as `derive --library FOLDER` counts it.
#[test]
fn every_kind_derives_as_its_command_does() {
    let dir = TempDir::new("studio-kinds");
    let copy = |name: &str, to: &str| {
        let path = dir.path(to);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::copy(example(name), &path).unwrap();
        std::fs::canonicalize(&path).unwrap()
    };
    let island = copy("koch-island.lsys", "koch-island.lsys");
    let tree = copy("tree-3d.lsys", "tree-3d.lsys");
    let grotto = copy("grotto.cave", "grotto.cave");
    let house = copy("topo_house.grammar", "topo_house.grammar");
    let chair = copy("chairs/chair.goal", "chairs/chair.goal");
    for material in ["fabric", "metal", "wood"] {
        copy(
            &format!("chairs/materials/{material}.goal"),
            &format!("chairs/materials/{material}.goal"),
        );
    }
    let studio = start(&[&island, &chair]);
    let text = |path: &std::path::Path| std::fs::read_to_string(path).unwrap();
    let out = |name: &str| dir.path(name).to_str().unwrap().to_owned();

    // 2D: the SVG `shapegram lsystem` writes, no GLB.
    let answer = derive(&studio, &island, &text(&island));
    shapegram(&[
        "lsystem",
        "-q",
        island.to_str().unwrap(),
        "-o",
        &out("island.svg"),
    ]);
    assert_eq!(
        (&answer["ok"], &answer["glb"], &answer["diagnostics"]),
        (&json!(true), &Value::Null, &json!([]))
    );
    assert_eq!(
        answer["svg"].as_str().unwrap(),
        std::fs::read_to_string(out("island.svg")).unwrap()
    );
    assert_eq!(
        answer["summary"],
        json!("3 steps, 3803 modules, 2048 segments, 0 polygons")
    );

    // 3D, a cave, a topological grammar: their commands' GLB files.
    for (path, command) in [
        (&tree, vec!["lsystem", "-q"]),
        (&grotto, vec!["cave", "-q"]),
        (&house, vec!["topo", "-q"]),
    ] {
        let answer = derive(&studio, path, &text(path));
        assert_eq!(answer["svg"], Value::Null, "{}", path.display());
        let written = out("written.glb");
        let mut args = command.clone();
        args.extend([path.to_str().unwrap(), "-o", &written]);
        shapegram(&args);
        let file = std::fs::read(&written).unwrap();
        assert!(
            glb_of(&answer) == file,
            "{} differs from {command:?}",
            path.display()
        );
        assert_eq!(answer["glb_bytes"], json!(file.len()));
    }

    // A goal grammar with the goal grammars of its folder (and subfolders) as its library.
    let answer = derive(&studio, &chair, &text(&chair));
    let stats = shapegram(&[
        "derive",
        "-q",
        "--stats",
        chair.to_str().unwrap(),
        "--library",
        chair.parent().unwrap().to_str().unwrap(),
    ]);
    let stats: Value = serde_json::from_slice(&stats.stdout).unwrap();
    assert_eq!(
        (&answer["ok"], &answer["shapes"], &answer["leaves"]),
        (&json!(true), &stats["shapes"], &stats["leaves"])
    );
    assert!(
        answer["summary"]
            .as_str()
            .unwrap()
            .ends_with("library of 3 files")
    );
}

/// Mistakes in every kind come back at their line and column, as the parsers report them.
#[test]
fn mistakes_in_every_kind_have_lines_and_columns() {
    let dir = TempDir::new("studio-kind-errors");
    let mut files = Vec::new();
    for name in ["plant.lsys", "cave.cave", "topo.grammar", "goals.goal"] {
        std::fs::write(dir.path(name), "").unwrap();
        files.push(std::fs::canonicalize(dir.path(name)).unwrap());
    }
    let studio = start(&[&files[0]]);
    let place = |answer: &Value| {
        let d = &answer["diagnostics"][0];
        (
            answer["ok"].clone(),
            d["severity"].clone(),
            d["line"].clone(),
            d["column"].clone(),
        )
    };
    let error_at =
        |line: usize, column: usize| (json!(false), json!("error"), json!(line), json!(column));
    let plant = derive(&studio, &files[0], "n: 2\naxiom: F\nF -> F(1,\n");
    assert_eq!(place(&plant), error_at(3, 10), "{plant}");
    let cave = derive(&studio, &files[1], "lod 4\nadd box(1, 0, 1)\n");
    assert_eq!(place(&cave), error_at(2, 5), "{cave}");
    assert_eq!(
        cave["diagnostics"][0]["message"],
        json!("invalid box size y 0: expected a finite number greater than 0")
    );
    let topo = derive(&studio, &files[2], "{\n  \"format\": 3,,\n}\n");
    assert_eq!(place(&topo), error_at(2, 13), "{topo}");
    assert_eq!(
        topo["diagnostics"][0]["message"],
        json!("invalid type: integer `3`, expected a string")
    );
    let goals = derive(
        &studio,
        &files[3],
        "axiom chair size(1, 1, 1)\nfulfills(chair) --> s(1, 1\n",
    );
    assert_eq!(place(&goals), error_at(2, 22), "{goals}");
    assert_eq!(goals["diagnostics"][0]["message"], json!("unclosed `(`"));
    // A problem without a place in the text: a field of the wrong type, named by its path.
    let house = std::fs::read_to_string(example("topo_house.grammar")).unwrap();
    let topo = derive(
        &studio,
        &files[2],
        &house.replace("\"version\": 1", "\"version\": 2"),
    );
    assert_eq!(topo["diagnostics"], json!([]));
    assert_eq!(
        topo["error"],
        json!(format!(
            "{}: version: version 2 is not supported (this build reads version 1)",
            files[2].display()
        ))
    );
}

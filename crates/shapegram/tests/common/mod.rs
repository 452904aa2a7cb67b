//! What the end-to-end tests of the `shapegram` binary share: scratch folders, the shipped
//! examples and running the binary.
#![allow(dead_code)]

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStderr, Command, Output, Stdio};
use std::sync::atomic::{AtomicUsize, Ordering};

use serde_json::Value;

/// A fresh directory under the system temp dir, removed on drop.
pub struct TempDir(PathBuf);

impl TempDir {
    /// A new directory named after the test (unique within the run).
    pub fn new(test: &str) -> Self {
        static COUNTER: AtomicUsize = AtomicUsize::new(0);
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        let dir =
            std::env::temp_dir().join(format!("shapegram-test-{}-{test}-{n}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        Self(dir)
    }

    /// A path inside the directory.
    pub fn path(&self, name: &str) -> PathBuf {
        self.0.join(name)
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// A file of the project's `examples/` folder.
pub fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name)
}

/// Runs the binary with `args`.
pub fn shapegram<S: AsRef<std::ffi::OsStr>>(args: &[S]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_shapegram"))
        .args(args)
        .output()
        .unwrap()
}

/// What a run of the binary wrote to stderr.
pub fn stderr(output: &Output) -> String {
    String::from_utf8(output.stderr.clone()).unwrap()
}

/// A `shapegram serve` child process, killed on drop.
pub struct Server {
    pub child: Child,
    /// `127.0.0.1:PORT`.
    pub addr: String,
    /// What it printed first.
    pub first_line: String,
    /// Its stderr, when it was started with a fail point.
    pub stderr: Option<ChildStderr>,
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Starts `shapegram serve` on a free port over the database `db`, once it accepts connections.
pub fn start_server(db: &Path) -> Server {
    start_server_with(db, None, &[])
}

/// Starts `shapegram serve` over `db` with more `options`, stopping at `fail_point` in a
/// publish (`SHAPEGRAM_FAILPOINT`); its stderr is piped then, to see it arrive there.
pub fn start_server_with(db: &Path, fail_point: Option<&str>, options: &[&str]) -> Server {
    start_server_over(&["--data".as_ref(), db.as_os_str()], fail_point, options)
}

/// [`start_server_with`] over the database arguments given (`--data FILE` or `--database URL`).
pub fn start_server_over(
    database: &[&std::ffi::OsStr],
    fail_point: Option<&str>,
    options: &[&str],
) -> Server {
    let mut command = Command::new(env!("CARGO_BIN_EXE_shapegram"));
    command
        .args(["serve", "--listen", "127.0.0.1:0"])
        .args(database)
        .args(options)
        .env_remove("SHAPEGRAM_FAILPOINT")
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit());
    if let Some(point) = fail_point {
        command
            .env("SHAPEGRAM_FAILPOINT", point)
            .stderr(Stdio::piped());
    }
    let mut child = command.spawn().unwrap();
    let stderr = child.stderr.take();
    let mut line = String::new();
    BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut line)
        .unwrap();
    let addr = line
        .split("listening on http://")
        .nth(1)
        .and_then(|rest| rest.split_whitespace().next())
        .unwrap_or_else(|| panic!("no address in {line:?}"))
        .to_owned();
    assert!(line.contains("listening"), "{line}");
    Server {
        child,
        addr,
        first_line: line,
        stderr,
    }
}

/// An answer: status, headers (lower-case names) and body.
pub struct Answer {
    pub status: u16,
    pub headers: Vec<(String, String)>,
    pub body: Vec<u8>,
}

impl Answer {
    /// A header's value.
    pub fn header(&self, name: &str) -> Option<&str> {
        self.headers
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_str())
    }

    /// The body as JSON (`null` when empty).
    pub fn json(&self) -> Value {
        if self.body.is_empty() {
            return Value::Null;
        }
        serde_json::from_slice(&self.body).unwrap_or_else(|e| {
            panic!(
                "{}: not JSON ({e}): {}",
                self.status,
                String::from_utf8_lossy(&self.body)
            )
        })
    }
}

/// One HTTP/1.1 request (the server closes the connection after it).
pub fn request(
    server: &Server,
    method: &str,
    path: &str,
    token: Option<&str>,
    body: Option<Value>,
) -> Answer {
    let mut stream = TcpStream::connect(&server.addr).unwrap();
    let body = body.map(|b| b.to_string()).unwrap_or_default();
    let auth = token
        .map(|t| format!("Authorization: Bearer {t}\r\n"))
        .unwrap_or_default();
    write!(
        stream,
        "{method} {path} HTTP/1.1\r\nHost: {}\r\nConnection: close\r\nContent-Type: application/json\r\nContent-Length: {}\r\n{auth}\r\n{body}",
        server.addr,
        body.len()
    )
    .unwrap();
    let mut answer = Vec::new();
    stream.read_to_end(&mut answer).unwrap();
    let end = answer
        .windows(4)
        .position(|w| w == b"\r\n\r\n")
        .expect("a header");
    let head = String::from_utf8(answer[..end].to_vec()).unwrap();
    let mut lines = head.split("\r\n");
    let status = lines.next().unwrap()[9..12].parse().unwrap();
    let headers = lines
        .filter_map(|l| l.split_once(':'))
        .map(|(n, v)| (n.trim().to_ascii_lowercase(), v.trim().to_owned()))
        .collect();
    Answer {
        status,
        headers,
        body: answer[end + 4..].to_vec(),
    }
}

/// One HTTP/1.1 request: the status and JSON body.
pub fn http(
    server: &Server,
    method: &str,
    path: &str,
    token: Option<&str>,
    body: Option<Value>,
) -> (u16, Value) {
    let answer = request(server, method, path, token, body);
    (answer.status, answer.json())
}

/// Signs `name` up (password `NAME's password`) and logs in: the token.
pub fn sign_up(server: &Server, name: &str) -> String {
    let credentials = serde_json::json!({"name": name, "password": format!("{name}'s password")});
    let (status, body) = http(
        server,
        "POST",
        "/api/v1/accounts",
        None,
        Some(credentials.clone()),
    );
    assert_eq!(status, 201, "{body}");
    let (status, login) = http(server, "POST", "/api/v1/login", None, Some(credentials));
    assert_eq!(status, 200, "{login}");
    login["token"].as_str().unwrap().to_owned()
}

/// The JSON chunk of a GLB file's bytes.
pub fn glb_json_of(bytes: &[u8]) -> Value {
    assert_eq!(&bytes[..4], b"glTF");
    let len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    serde_json::from_slice(&bytes[20..20 + len]).unwrap()
}

/// Checks that three GLB files written without a flag, with `--quantize` and with `--meshopt`
/// hold the same model: each requires just the extensions its encoding needs, all read back
/// with the same parts and triangles, the quantised positions within half a grid step of the
/// float ones, and the compressed file decodes to the quantised one (its triangles perhaps
/// starting at another corner).
pub fn check_glb_encodings(float: &Path, quantized: &Path, compressed: &Path) {
    let required = |path: &Path| -> Vec<String> {
        let json = glb_json_of(&std::fs::read(path).unwrap());
        let names = json["extensionsRequired"].as_array().cloned();
        let names = names.unwrap_or_default().into_iter();
        names.map(|v| v.as_str().unwrap().to_owned()).collect()
    };
    assert!(required(float).is_empty());
    assert_eq!(required(quantized), ["KHR_mesh_quantization"]);
    assert_eq!(
        required(compressed),
        ["KHR_mesh_quantization", "EXT_meshopt_compression"]
    );
    let [float, quantized, compressed] =
        [float, quantized, compressed].map(|path| shapegram_export::load(path).unwrap());
    // The index codec may start a triangle at another corner; nothing else changes.
    let triangles = |model: &shapegram_geom::Model| -> Vec<Vec<[u32; 3]>> {
        let part = |p: &shapegram_geom::Part| {
            let mut faces: Vec<[u32; 3]> = (0..p.mesh.face_count())
                .map(|f| {
                    let t = p.mesh.face(f);
                    let first = (0..3).min_by_key(|&k| t[k]).unwrap();
                    [0, 1, 2].map(|k| t[(first + k) % 3])
                })
                .collect();
            faces.sort_unstable();
            faces
        };
        model.parts.iter().map(part).collect()
    };
    assert_eq!(triangles(&compressed), triangles(&quantized));
    for (c, q) in compressed.parts.iter().zip(&quantized.parts) {
        assert_eq!(c.mesh.positions(), q.mesh.positions());
        assert_eq!(c.normals, q.normals);
    }
    assert_eq!(float.parts.len(), quantized.parts.len());
    let bounds = float.merged_mesh().bounds().unwrap();
    // A grid of ±32,767 steps over the largest extent, from the centre.
    let step = (bounds.max - bounds.min).max_element() / 65534.0;
    for (a, b) in float.parts.iter().zip(&quantized.parts) {
        assert_eq!(a.mesh.face_count(), b.mesh.face_count(), "{}", a.name);
        assert_eq!(a.mesh.vertex_count(), b.mesh.vertex_count(), "{}", a.name);
        assert_eq!(a.normals.len(), b.normals.len(), "{}", a.name);
        for (p, q) in a.mesh.positions().iter().zip(b.mesh.positions()) {
            assert!((*p - *q).abs().max_element() <= step, "{p} against {q}");
        }
    }
}

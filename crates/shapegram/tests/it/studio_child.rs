//! `shapegram studio` as a child process on a free loopback port, and requests to it as the
//! studio's page sends them (its Host and Origin).

use std::ffi::OsStr;
use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::process::{Child, Command, Stdio};

use serde_json::Value;

/// A `shapegram studio` child, killed on drop.
pub struct Studio {
    child: Child,
    /// `127.0.0.1:PORT`.
    pub addr: String,
}

impl Drop for Studio {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Starts `shapegram studio` with `args` (files, options) on a free port, once it has printed
/// its address.
pub fn start(args: &[&OsStr]) -> Studio {
    let mut child = Command::new(env!("CARGO_BIN_EXE_shapegram"))
        .arg("studio")
        .args(args)
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

/// A request from the studio's page to the studio at `addr`: the status and JSON body.
pub fn send(addr: &str, method: &str, path: &str, body: Option<&Value>) -> (u16, Value) {
    let mut stream = TcpStream::connect(addr).unwrap();
    let body = body.map(Value::to_string).unwrap_or_default();
    write!(
        stream,
        "{method} {path} HTTP/1.1\r\nHost: {addr}\r\nOrigin: http://{addr}\r\nConnection: close\r\nContent-Type: application/json\r\nContent-Length: {}\r\n\r\n{body}",
        body.len(),
    )
    .unwrap();
    let mut answer = String::new();
    stream.read_to_string(&mut answer).unwrap();
    let status: u16 = answer[9..12].parse().unwrap();
    let (_, content) = answer.split_once("\r\n\r\n").unwrap();
    (status, serde_json::from_str(content).unwrap())
}

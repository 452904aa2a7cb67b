//! End to end: `shapegram repo …` against a `shapegram serve` child process, each user with
//! their own configuration folder: sign-up and login, publishing the chair example's
//! materials, search, fetch, friends-only grammars, logout, errors.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

use crate::common;

use common::{Server, TempDir, example, http, sign_up, start_server};
use serde_json::json;

/// A user of the command line: a configuration folder and a repository.
struct User {
    config: PathBuf,
    repo: String,
}

/// What a run printed, and how it ended.
#[derive(Debug)]
struct Run {
    code: i32,
    stdout: String,
    stderr: String,
}

impl Run {
    fn of(output: Output) -> Run {
        Run {
            code: output.status.code().expect("an exit code"),
            stdout: String::from_utf8(output.stdout).unwrap(),
            stderr: String::from_utf8(output.stderr).unwrap(),
        }
    }

    /// Asserts success; the run itself.
    fn ok(self) -> Run {
        assert_eq!(self.code, 0, "{self:?}");
        self
    }
}

impl User {
    fn new(dir: &TempDir, name: &str, server: &Server) -> User {
        User {
            config: dir.path(&format!("{name}-config")),
            repo: format!("http://{}", server.addr),
        }
    }

    fn command(&self, args: &[&str]) -> Command {
        let mut command = Command::new(env!("CARGO_BIN_EXE_shapegram"));
        command
            .arg("repo")
            .args(args)
            .args(["--repo", &self.repo])
            .env("SHAPEGRAM_CONFIG_DIR", &self.config)
            .env_remove("SHAPEGRAM_TOKEN")
            .env_remove("SHAPEGRAM_REPO");
        command
    }

    /// Runs `shapegram repo ARGS --repo URL` with no standard input.
    fn run(&self, args: &[&str]) -> Run {
        Run::of(self.command(args).stdin(Stdio::null()).output().unwrap())
    }

    /// Runs it with `input` on standard input.
    fn run_with_input(&self, args: &[&str], input: &str) -> Run {
        let mut child = self
            .command(args)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        std::io::Write::write_all(&mut child.stdin.take().unwrap(), input.as_bytes()).unwrap();
        Run::of(child.wait_with_output().unwrap())
    }

    fn credentials(&self) -> serde_json::Value {
        let text = std::fs::read_to_string(self.config.join("credentials.json")).unwrap();
        serde_json::from_str(&text).unwrap()
    }
}

fn material(name: &str) -> PathBuf {
    example(&format!("chairs/materials/{name}.goal"))
}

fn path(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn publish_search_fetch_and_friends_through_the_command_line() {
    let dir = TempDir::new("repo-cli");
    let server = start_server(&dir.path("repo.db"));
    let ana = User::new(&dir, "ana", &server);
    let bob = User::new(&dir, "bob", &server);
    let url = &ana.repo;

    let run = ana
        .run_with_input(&["signup", "ana", "--password-stdin"], "ana's password\n")
        .ok();
    assert_eq!(
        run.stderr,
        format!(
            "signed up at {url} as ana\nlogged in to {url} as ana (token stored in {})\n",
            ana.config.join("credentials.json").display()
        )
    );
    bob.run_with_input(&["signup", "bob", "--password-stdin"], "bob's password")
        .ok();
    let taken = ana.run_with_input(&["signup", "Ana", "--password-stdin"], "another password");
    assert_eq!(
        (taken.code, taken.stderr.as_str()),
        (1, "error: the name Ana is taken\n")
    );

    // Login with the password on standard input; the token lands in a private file, and the
    // one it replaces is revoked.
    let wrong = ana.run_with_input(&["login", "ana", "--password-stdin"], "not it\n");
    assert_eq!(
        (wrong.code, wrong.stderr.as_str()),
        (1, "error: wrong name or password\n")
    );
    let first_token = ana.credentials()["repositories"][url]["token"].clone();
    ana.run_with_input(&["login", "ANA", "--password-stdin"], "ana's password\n")
        .ok();
    let stored = &ana.credentials()["repositories"][url];
    assert_eq!(stored["name"], "ana");
    assert!(stored["token"].as_str().unwrap().starts_with("sgr_"));
    assert_ne!(stored["token"], first_token);
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let meta = std::fs::metadata(ana.config.join("credentials.json")).unwrap();
        assert_eq!(meta.permissions().mode() & 0o777, 0o600);
    }
    assert_eq!(ana.run(&["whoami"]).ok().stdout, "ana\n");

    // Publish the chair example's materials; search finds them by goal.
    for (name, rules) in [("fabric", 2), ("metal", 2), ("wood", 1)] {
        let run = ana.run(&["publish", path(&material(name))]).ok();
        let noun = if rules == 1 { "rule" } else { "rules" };
        assert_eq!(
            run.stdout,
            format!("published ana/{name}@1 ({rules} {noun}, 0 warnings)\n")
        );
    }
    let table = "GRAMMAR     VERSION  VISIBILITY\n\
                 ana/fabric  1        public\n\
                 ana/metal   1        public\n\
                 ana/wood    1        public\n";
    assert_eq!(bob.run(&["search", "--goal", "wooden"]).ok().stdout, table);
    assert_eq!(
        bob.run(&["search", "--goal", "metallic"]).ok().stdout,
        "GRAMMAR    VERSION  VISIBILITY\nana/metal  1        public\n"
    );
    assert_eq!(
        bob.run(&["search", "wo"]).ok().stdout,
        "GRAMMAR   VERSION  VISIBILITY\nana/wood  1        public\n"
    );
    let none = bob.run(&["search", "--tag", "chair"]).ok();
    assert_eq!(
        (none.stdout.as_str(), none.stderr.as_str()),
        ("", "no grammars found\n")
    );

    // Fetch round-trips byte for byte, to stdout or a file.
    let wood = std::fs::read(material("wood")).unwrap();
    assert_eq!(bob.run(&["fetch", "ana/wood"]).ok().stdout.as_bytes(), wood);
    let out = dir.path("metal.goal");
    let run = bob.run(&["fetch", "ana/metal@1", "-o", path(&out)]).ok();
    assert_eq!(
        run.stderr,
        format!("wrote {} (ana/metal@1)\n", out.display())
    );
    assert_eq!(
        std::fs::read(&out).unwrap(),
        std::fs::read(material("metal")).unwrap()
    );
    let versions = bob.run(&["versions", "ana/wood"]).ok().stdout;
    let lines: Vec<&str> = versions.lines().collect();
    assert_eq!(lines.len(), 2, "{versions}");
    assert!(
        lines[0].starts_with("VERSION  PUBLISHED (UTC)"),
        "{versions}"
    );
    assert!(lines[1].starts_with("1        20"), "{versions}");
    assert!(lines[1].ends_with(&shapegram_sha256(&wood)), "{versions}");

    // A friends-only grammar: invisible to a stranger, visible once friends.
    let run = ana
        .run(&[
            "publish",
            path(&material("wood")),
            "--name",
            "oak",
            "--visibility",
            "friends",
        ])
        .ok();
    assert_eq!(run.stdout, "published ana/oak@1 (1 rule, 0 warnings)\n");
    assert_eq!(bob.run(&["search", "--goal", "wooden"]).ok().stdout, table);
    let hidden = bob.run(&["fetch", "ana/oak"]);
    assert_eq!(
        (hidden.code, hidden.stderr.as_str()),
        (1, "error: not found\n")
    );
    let asked = bob.run(&["friends", "add", "ana"]).ok();
    assert_eq!(
        asked.stderr,
        "asked ana to be friends: waiting for them to accept\n"
    );
    assert_eq!(
        ana.run(&["friends"]).ok().stdout,
        "NAME  STATE\nbob   asks you (accept with `friends accept NAME`)\n"
    );
    assert_eq!(
        bob.run(&["search", "--goal", "wooden"]).ok().stdout,
        table,
        "a request is not a friendship"
    );
    ana.run(&["friends", "accept", "bob"]).ok();
    assert_eq!(
        bob.run(&["friends"]).ok().stdout,
        "NAME  STATE\nana   friends\n"
    );
    assert_eq!(
        bob.run(&["search", "--goal", "wooden"]).ok().stdout,
        "GRAMMAR     VERSION  VISIBILITY\n\
         ana/fabric  1        public\n\
         ana/metal   1        public\n\
         ana/oak     1        friends\n\
         ana/wood    1        public\n"
    );
    assert_eq!(bob.run(&["fetch", "ana/oak"]).ok().stdout.as_bytes(), wood);

    // A grammar with an error: its line and column, nothing published.
    let broken = dir.path("broken.goal");
    std::fs::write(
        &broken,
        "// Two rules.\nfulfills(wooden) --> colour(\"#8b5a2b\")\n",
    )
    .unwrap();
    let run = ana.run(&["publish", path(&broken)]);
    assert_eq!(run.code, 1, "{run:?}");
    let first = run.stderr.lines().next().unwrap();
    assert!(
        first.starts_with(&format!("{}:2:22: error: ", broken.display())),
        "{}",
        run.stderr
    );
    assert!(
        run.stderr
            .ends_with("error: broken does not compile: nothing published\n"),
        "{}",
        run.stderr
    );
    assert_eq!(
        ana.run(&["fetch", "ana/broken"]).stderr,
        "error: not found\n"
    );

    // A token for CI: printed once, sent through SHAPEGRAM_TOKEN, listed, revoked.
    let made = ana.run(&["tokens", "new", "ci"]).ok();
    let ci = made.stdout.trim_end().to_owned();
    assert!(
        ci.starts_with("sgr_") && made.stdout.ends_with('\n'),
        "{made:?}"
    );
    let as_ci = |args: &[&str]| {
        Run::of(
            bob.command(args)
                .env("SHAPEGRAM_TOKEN", &ci)
                .output()
                .unwrap(),
        )
    };
    assert_eq!(
        as_ci(&["whoami"]).ok().stdout,
        "ana\n",
        "the token overrides bob's login"
    );
    let list = ana.run(&["tokens"]).ok().stdout;
    let rows: Vec<(&str, &str, &str)> = list
        .lines()
        .map(|l| {
            let cells: Vec<&str> = l.split_whitespace().collect();
            (cells[0], cells[1], *cells.last().unwrap())
        })
        .collect();
    assert_eq!(
        rows,
        [
            ("ID", "NAME", "STATE"),
            ("1", "login", "revoked"),
            ("3", "login", "active"),
            ("4", "ci", "active")
        ],
        "{list}"
    );
    assert_eq!(
        ana.run(&["tokens", "revoke", "4"]).ok().stderr,
        "revoked token 4\n"
    );
    assert_eq!(as_ci(&["whoami"]).code, 1);
    let other = ana.run(&["tokens", "revoke", "2"]);
    assert_eq!(
        (other.code, other.stderr.as_str()),
        (1, "error: not found\n")
    );

    // Logout revokes the token: sent again, the server refuses it.
    let token = ana.credentials()["repositories"][url]["token"]
        .as_str()
        .unwrap()
        .to_owned();
    let run = ana.run(&["logout"]).ok();
    assert_eq!(run.stderr, format!("logged out of {url} (ana)\n"));
    assert!(
        ana.credentials()["repositories"]
            .as_object()
            .unwrap()
            .is_empty()
    );
    let run = ana.run(&["whoami"]);
    assert_eq!(
        (run.code, run.stderr.as_str()),
        (
            1,
            format!(
                "error: not logged in to {url}\n  = hint: log in with `shapegram repo login --repo {url}`\n"
            )
            .as_str()
        )
    );
    let revoked = Run::of(
        ana.command(&["whoami"])
            .env("SHAPEGRAM_TOKEN", &token)
            .output()
            .unwrap(),
    );
    assert_eq!(revoked.code, 1, "{revoked:?}");
    assert!(
        revoked
            .stderr
            .starts_with("error: unknown or revoked API token\n"),
        "{}",
        revoked.stderr
    );
}

/// The SHA-256 the repository reports for a text, in hex.
fn shapegram_sha256(bytes: &[u8]) -> String {
    shapegram_server::tokens::sha256_hex(bytes)
}

#[test]
fn usage_and_connection_errors_exit_with_2() {
    let dir = TempDir::new("repo-cli-errors");
    // A port that was free a moment ago: nothing listens there.
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port();
    let user = User {
        config: dir.path("config"),
        repo: format!("http://127.0.0.1:{port}"),
    };
    let run = user.run(&["search", "--goal", "wooden"]);
    assert_eq!(
        (run.code, run.stderr),
        (
            2,
            format!(
                "error: cannot connect to http://127.0.0.1:{port}: connection refused (is \
                 `shapegram serve` running there?)\n"
            )
        )
    );
    let run = user.run(&["fetch", "wood"]);
    assert_eq!(
        (run.code, run.stderr.as_str()),
        (
            2,
            "error: wood does not name a grammar: write OWNER/NAME or OWNER/NAME@VERSION\n"
        )
    );
    let run = user.run(&["login", "--password-stdin"]);
    assert_eq!(
        (run.code, run.stderr.as_str()),
        (
            2,
            "error: give the account's name: `shapegram repo login NAME --password-stdin`\n"
        )
    );
    let ftp = User {
        config: dir.path("config"),
        repo: "ftp://example.org".into(),
    };
    let run = ftp.run(&["whoami"]);
    assert_eq!(
        (run.code, run.stderr.as_str()),
        (
            2,
            "error: ftp://example.org is not a repository URL: it is http://HOST[:PORT] or \
             https://HOST[:PORT]\n"
        )
    );
    let run = user.run(&["publish", "--visibility", "everyone", "x.goal"]);
    assert_eq!(run.code, 2, "{run:?}");
}

#[test]
fn fetch_without_a_version_skips_yanked_versions() {
    let dir = TempDir::new("repo-yank");
    let server = start_server(&dir.path("repo.db"));
    let token = &sign_up(&server, "ana");
    let texts = [
        "fulfills(wooden) --> color(\"#8b5a2b\")\n",
        "fulfills(wooden) --> color(\"#806040\")\n",
    ];
    for text in texts {
        let (status, body) = http(
            &server,
            "POST",
            "/api/v1/grammars/ana/wood/versions",
            Some(token),
            Some(json!({"text": text})),
        );
        assert_eq!(status, 201, "{body}");
    }
    let bob = User::new(&dir, "bob", &server);
    let ana = User::new(&dir, "ana", &server);
    ana.run_with_input(&["login", "ana", "--password-stdin"], "ana's password\n")
        .ok();
    let yank = |version: i64| {
        let run = ana.run(&[
            "yank",
            &format!("ana/wood@{version}"),
            "--reason",
            "too dark",
        ]);
        assert_eq!(
            run.ok().stderr,
            format!(
                "yanked ana/wood@{version}: new resolutions and searches skip it; locks that \
                 name it keep it\n"
            )
        );
    };
    // Only a version is yanked, by someone logged in.
    let run = ana.run(&["yank", "ana/wood"]);
    assert_eq!(
        (run.code, run.stderr.as_str()),
        (
            2,
            "error: ana/wood names no version: yank OWNER/NAME@VERSION\n"
        )
    );
    let run = bob.run(&["yank", "ana/wood@1"]);
    assert_eq!(run.code, 1, "{run:?}");
    assert!(
        run.stderr.starts_with("error: not logged in to http://"),
        "{run:?}"
    );
    yank(2);
    assert_eq!(bob.run(&["fetch", "ana/wood"]).ok().stdout, texts[0]);
    // A yanked version is still fetched by its number.
    assert_eq!(bob.run(&["fetch", "ana/wood@2"]).ok().stdout, texts[1]);
    let versions = bob.run(&["versions", "ana/wood"]).ok().stdout;
    let yanked: Vec<bool> = versions
        .lines()
        .skip(1)
        .map(|l| l.contains(" yanked "))
        .collect();
    assert_eq!(yanked, [false, true], "{versions}");
    // Undone, and done again.
    let run = ana.run(&["yank", "ana/wood@2", "--undo"]);
    assert_eq!(run.ok().stderr, "ana/wood@2 is offered again\n");
    assert_eq!(bob.run(&["fetch", "ana/wood"]).ok().stdout, texts[1]);
    yank(2);
    yank(1);
    let run = bob.run(&["fetch", "ana/wood"]);
    assert_eq!(run.code, 1, "{run:?}");
    assert_eq!(
        run.stderr,
        "error: every version of ana/wood is yanked: name one (ana/wood@VERSION)\n"
    );
}

//! End to end: `shapegram derive --repo` against a `shapegram serve` child process. A chair
//! whose material is published by someone else: found by its goal, locked, reproduced byte
//! for byte after a new version is published and with the server gone, updated on request;
//! and the errors of every misuse.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

use crate::common;

use common::{Server, TempDir, example, http, start_server};

/// Runs the binary with a configuration folder and a cache of the test's own.
fn run(dir: &TempDir, args: &[&str], input: Option<&str>) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_shapegram"))
        .args(args)
        .env("SHAPEGRAM_CONFIG_DIR", dir.path("config"))
        .env("SHAPEGRAM_CACHE_DIR", dir.path("cache"))
        .env_remove("SHAPEGRAM_TOKEN")
        .env_remove("SHAPEGRAM_REPO")
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdin = child.stdin.take().unwrap();
    if let Some(input) = input {
        std::io::Write::write_all(&mut stdin, input.as_bytes()).unwrap();
    }
    drop(stdin);
    child.wait_with_output().unwrap()
}

fn ok(output: Output) -> String {
    let stderr = String::from_utf8(output.stderr).unwrap();
    assert!(output.status.success(), "{stderr}");
    stderr
}

fn failed(output: Output) -> String {
    let stderr = String::from_utf8(output.stderr).unwrap();
    assert!(!output.status.success(), "{stderr}");
    stderr
}

fn url(server: &Server) -> String {
    format!("http://{}", server.addr)
}

/// Ana signs up and publishes `text` as `ana/NAME`.
fn publish(dir: &TempDir, server: &Server, name: &str, text: &str) {
    let repo = url(server);
    if !dir.path("config").exists() {
        let args = ["repo", "signup", "ana", "--password-stdin", "--repo", &repo];
        ok(run(dir, &args, Some("ana's password\n")));
    }
    let file = dir.path(&format!("{name}.goal"));
    std::fs::write(&file, text).unwrap();
    let file = file.to_str().unwrap();
    ok(run(dir, &["repo", "publish", file, "--repo", &repo], None));
    std::fs::remove_file(file).unwrap();
}

/// The chair example, alone in a folder of the test's (its lock goes beside it).
fn chair(dir: &TempDir) -> PathBuf {
    let chair = dir.path("work/chair.goal");
    std::fs::create_dir_all(chair.parent().unwrap()).unwrap();
    std::fs::copy(example("chairs/chair.goal"), &chair).unwrap();
    chair
}

fn derive(dir: &TempDir, chair: &Path, out: &str, more: &[&str]) -> Output {
    let out = dir.path(out);
    let mut args = vec![
        "derive",
        chair.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(more);
    run(dir, &args, None)
}

fn lock(chair: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(chair.with_file_name("chair.goal.lock")).unwrap();
    serde_json::from_str(&text).unwrap()
}

const RED_WOOD: &str = "fulfills(wooden) --> color(\"#aa2020\")\n";

#[test]
fn a_derivation_finds_locks_and_reproduces_the_repositorys_rules() {
    let dir = TempDir::new("repo-derive");
    let server = start_server(&dir.path("repo.db"));
    let repo = url(&server);
    let wood = std::fs::read_to_string(example("chairs/materials/wood.goal")).unwrap();
    publish(&dir, &server, "wood", &wood);
    let chair = chair(&dir);

    // Found by its goal: the same model as with the material in a local library.
    let stderr = ok(derive(&dir, &chair, "found.glb", &["--repo", &repo]));
    assert!(
        stderr.contains(&format!(
            "repository {repo} (link all): 1 grammar (ana/wood@1) from 5 queries in 2 rounds, \
             locked in {}",
            chair.with_file_name("chair.goal.lock").display()
        )),
        "{stderr}"
    );
    let materials = example("chairs/materials/wood.goal");
    let local = dir.path("local.glb");
    ok(run(
        &dir,
        &[
            "derive",
            example("chairs/chair.goal").to_str().unwrap(),
            "--library",
            materials.to_str().unwrap(),
            "-o",
            local.to_str().unwrap(),
        ],
        None,
    ));
    let found = std::fs::read(dir.path("found.glb")).unwrap();
    assert_eq!(found, std::fs::read(&local).unwrap());
    let locked = lock(&chair);
    assert_eq!(locked["lock"], 1);
    assert_eq!(locked["repository"], repo.as_str());
    assert_eq!(locked["link"], "all");
    assert_eq!(locked["as_of"], 1);
    let grammars = locked["grammars"].as_array().unwrap();
    assert_eq!(grammars.len(), 1);
    assert_eq!(
        (
            &grammars[0]["owner"],
            &grammars[0]["name"],
            &grammars[0]["version"]
        ),
        (&"ana".into(), &"wood".into(), &1.into())
    );
    assert_eq!(
        grammars[0]["sha256"],
        shapegram_server::tokens::sha256_hex(wood.as_bytes())
    );

    // Ana paints her wood red in version 2: the lock keeps the chair brown, byte for byte.
    publish(&dir, &server, "wood", RED_WOOD);
    let stderr = ok(derive(&dir, &chair, "again.glb", &[]));
    assert!(
        stderr.contains(&format!(
            "repository {repo} (link all): 1 grammar (ana/wood@1) as locked"
        )),
        "{stderr}"
    );
    assert_eq!(std::fs::read(dir.path("again.glb")).unwrap(), found);

    // Without the server, the cache has the locked text.
    drop(server);
    ok(derive(&dir, &chair, "cached.glb", &[]));
    assert_eq!(std::fs::read(dir.path("cached.glb")).unwrap(), found);
    ok(derive(&dir, &chair, "offline.glb", &["--offline"]));
    assert_eq!(std::fs::read(dir.path("offline.glb")).unwrap(), found);
    // Nor can it fetch what the cache lacks.
    std::fs::remove_dir_all(dir.path("cache")).unwrap();
    let stderr = failed(derive(&dir, &chair, "x.glb", &["--offline"]));
    assert!(
        stderr.contains(
            "error: ana/wood@1 is not in the cache, and --offline asks nothing of the repository"
        ),
        "{stderr}"
    );
    let stderr = failed(derive(&dir, &chair, "x.glb", &[]));
    assert!(
        stderr.contains(&format!(
            "error: cannot fetch ana/wood@1: cannot connect to {repo}"
        )),
        "{stderr}"
    );

    // The server again (on another port): --update finds version 2, and the chair is red.
    let server = start_server(&dir.path("repo.db"));
    let repo = url(&server);
    let stderr = failed(derive(&dir, &chair, "x.glb", &["--repo", &repo]));
    assert!(
        stderr.contains("was made with the repository http://"),
        "{stderr}"
    );
    ok(derive(
        &dir,
        &chair,
        "updated.glb",
        &["--repo", &repo, "--update"],
    ));
    let locked = lock(&chair);
    assert_eq!(locked["grammars"][0]["version"], 2);
    assert_eq!(locked["as_of"], 2);
    let updated = std::fs::read(dir.path("updated.glb")).unwrap();
    assert_ne!(updated, found);
    // A fresh cache fetches the locked version by its hash, and checks it.
    std::fs::remove_dir_all(dir.path("cache")).unwrap();
    ok(derive(&dir, &chair, "fetched.glb", &[]));
    assert_eq!(std::fs::read(dir.path("fetched.glb")).unwrap(), updated);
    // Ana renames her grammar: the lock still finds its text. (Logins are kept per URL, and
    // the server has another port now.)
    let login = ["repo", "login", "ana", "--password-stdin", "--repo", &repo];
    ok(run(&dir, &login, Some("ana's password\n")));
    let stderr = ok(run(
        &dir,
        &["repo", "rename", "ana/wood", "timber", "--repo", &repo],
        None,
    ));
    assert_eq!(stderr, "renamed ana/wood to ana/timber\n");
    std::fs::remove_dir_all(dir.path("cache")).unwrap();
    ok(derive(&dir, &chair, "renamed.glb", &[]));
    assert_eq!(std::fs::read(dir.path("renamed.glb")).unwrap(), updated);
    // --update alone asks the lock's repository again: nothing new, the same model.
    let stderr = ok(derive(&dir, &chair, "again-updated.glb", &["--update"]));
    assert!(stderr.contains("1 grammar (ana/timber@2)"), "{stderr}");
    assert_eq!(
        std::fs::read(dir.path("again-updated.glb")).unwrap(),
        updated
    );
    // `--link this` leaves the repository out: the chair has no material.
    let stderr = ok(derive(&dir, &chair, "alone.glb", &["--link", "this"]));
    assert!(!stderr.contains("repository"), "{stderr}");
    assert_ne!(std::fs::read(dir.path("alone.glb")).unwrap(), updated);
}

#[test]
fn a_yanked_version_still_derives_from_its_lock_and_update_resolves_without_it() {
    let dir = TempDir::new("repo-derive-yank");
    let server = start_server(&dir.path("repo.db"));
    let repo = url(&server);
    let wood = std::fs::read_to_string(example("chairs/materials/wood.goal")).unwrap();
    publish(&dir, &server, "wood", &wood);
    publish(&dir, &server, "wood", RED_WOOD);
    let chair = chair(&dir);
    ok(derive(&dir, &chair, "red.glb", &["--repo", &repo]));
    assert_eq!(lock(&chair)["grammars"][0]["version"], 2);
    let red = std::fs::read(dir.path("red.glb")).unwrap();

    // Ana yanks the red version.
    let credentials = serde_json::json!({"name": "ana", "password": "ana's password"});
    let (_, login) = http(&server, "POST", "/api/v1/login", None, Some(credentials));
    let token = login["token"].as_str().unwrap();
    let uri = "/api/v1/grammars/ana/wood/versions/2/yank";
    let (status, body) = http(&server, "POST", uri, Some(token), None);
    assert_eq!(status, 200, "{body}");

    // The lock still names it, and it is fetched by its number: the same red chair.
    std::fs::remove_dir_all(dir.path("cache")).unwrap();
    ok(derive(&dir, &chair, "locked.glb", &[]));
    assert_eq!(std::fs::read(dir.path("locked.glb")).unwrap(), red);
    assert_eq!(lock(&chair)["grammars"][0]["version"], 2);
    // A new resolution does without it: version 1, brown.
    let stderr = ok(derive(
        &dir,
        &chair,
        "brown.glb",
        &["--repo", &repo, "--update"],
    ));
    assert!(stderr.contains("1 grammar (ana/wood@1)"), "{stderr}");
    assert_eq!(lock(&chair)["grammars"][0]["version"], 1);
    assert_ne!(std::fs::read(dir.path("brown.glb")).unwrap(), red);
}

#[test]
fn misuses_of_the_repository_options_are_explained() {
    let dir = TempDir::new("repo-derive-errors");
    let chair = chair(&dir);
    let stderr = failed(derive(&dir, &chair, "x.glb", &["--offline"]));
    assert!(
        stderr.contains("error: --offline needs a lock file:"),
        "{stderr}"
    );
    let stderr = failed(derive(&dir, &chair, "x.glb", &["--update"]));
    assert!(
        stderr.contains("error: --update needs a repository: give --repo URL"),
        "{stderr}"
    );
    let stderr = failed(derive(
        &dir,
        &chair,
        "x.glb",
        &["--offline", "--repo", "http://127.0.0.1:9"],
    ));
    assert!(
        stderr.contains("error: --offline needs a lock file:"),
        "{stderr}"
    );
    // Nobody listens on port 9 (discard): the URL is named.
    let stderr = failed(derive(
        &dir,
        &chair,
        "x.glb",
        &["--repo", "http://127.0.0.1:9"],
    ));
    assert!(
        stderr.contains("error: cannot ask http://127.0.0.1:9 for rules: cannot connect to"),
        "{stderr}"
    );
    assert!(!chair.with_file_name("chair.goal.lock").exists());
    // A lock that is not one.
    std::fs::write(chair.with_file_name("chair.goal.lock"), "{\"lock\": 1}").unwrap();
    let stderr = failed(derive(&dir, &chair, "x.glb", &[]));
    assert!(
        stderr.contains("chair.goal.lock is not a lock file: missing field"),
        "{stderr}"
    );
    // Symbol grammars have no goals to ask for.
    let house = example("house.cga");
    let out = dir.path("house.glb");
    let args = [
        "derive",
        house.to_str().unwrap(),
        "--repo",
        "http://127.0.0.1:9",
        "-o",
        out.to_str().unwrap(),
    ];
    let stderr = failed(run(&dir, &args, None));
    assert!(
        stderr.contains(
            "house.cga is not a goal grammar: --repo, --link, --update and --offline find rules for goal grammars"
        ),
        "{stderr}"
    );
}

#[test]
fn link_modes_other_than_all_need_a_login() {
    let dir = TempDir::new("repo-derive-link");
    let server = start_server(&dir.path("repo.db"));
    let chair = chair(&dir);
    let stderr = failed(derive(
        &dir,
        &chair,
        "x.glb",
        &["--repo", &url(&server), "--link", "mine"],
    ));
    assert!(
        stderr.contains("link `mine` needs a token: it is about whose grammars are yours"),
        "{stderr}"
    );
}

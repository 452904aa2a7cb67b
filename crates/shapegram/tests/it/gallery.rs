//! The example gallery (`docs/examples.md`) stays true to `examples/`: every grammar there is
//! shown or named, and every picture it shows exists.

use std::path::Path;

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

/// The grammar files and rule packages at the top of `examples/` (the goal grammars live in folders of their own,
/// with their pictures in docs/goals.md; projects have their compiled `.grammar` beside them).
fn examples() -> Vec<String> {
    let kinds = ["cga", "mul", "sgl", "lsys", "cave", "grammar", "rpk"];
    let mut names: Vec<String> = std::fs::read_dir(root().join("examples"))
        .unwrap()
        .map(|entry| entry.unwrap().file_name().into_string().unwrap())
        .filter(|name| kinds.iter().any(|kind| name.ends_with(&format!(".{kind}"))))
        .collect();
    names.sort();
    names
}

#[test]
fn the_gallery_names_every_example() {
    let gallery = std::fs::read_to_string(root().join("docs/examples.md")).unwrap();
    let missing: Vec<String> = examples()
        .into_iter()
        .filter(|name| !gallery.contains(&format!("`{name}`")))
        .collect();
    assert!(
        missing.is_empty(),
        "docs/examples.md does not name {missing:?}"
    );
}

#[test]
fn every_picture_of_the_gallery_exists_and_shows_an_example() {
    let gallery = std::fs::read_to_string(root().join("docs/examples.md")).unwrap();
    let examples = examples();
    let pictures: Vec<&str> = gallery
        .split("](images/examples/")
        .skip(1)
        .map(|rest| &rest[..rest.find(')').unwrap()])
        .collect();
    assert_eq!(pictures.len(), 39, "pictures in docs/examples.md");
    for picture in pictures {
        let path = root().join("docs/images/examples").join(picture);
        assert!(
            path.is_file(),
            "{} is missing: run docs/gallery/render.sh",
            path.display()
        );
        let shown = picture.strip_suffix(".jpg").unwrap();
        assert!(
            examples.iter().any(|name| name.replace('.', "-") == shown),
            "{picture} shows no example in examples/"
        );
    }
}

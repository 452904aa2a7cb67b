//! "Did you mean …?" suggestions.

use shapegram_syntax::suggest;

const RULES: [&str; 6] = ["Facade", "Floor", "Window", "Wall", "Roof", "GroundFloor"];

#[test]
fn typos_find_the_intended_name() {
    assert_eq!(suggest("Facde", RULES), Some("Facade"));
    assert_eq!(suggest("Flor", RULES), Some("Floor"));
    assert_eq!(suggest("Windw", RULES), Some("Window"));
    assert_eq!(suggest("Rof", RULES), Some("Roof"));
    assert_eq!(suggest("GroundFlor", RULES), Some("GroundFloor"));
    assert_eq!(suggest("Wal", RULES), Some("Wall"));
}

#[test]
fn case_only_differences_are_always_close() {
    assert_eq!(suggest("facade", RULES), Some("Facade"));
    assert_eq!(suggest("GROUNDFLOOR", RULES), Some("GroundFloor"));
}

#[test]
fn ties_prefer_the_case_insensitive_match_then_the_first() {
    assert_eq!(suggest("wall", ["Walls", "Wall"]), Some("Wall"));
    assert_eq!(suggest("Bx", ["Ax", "Cx"]), Some("Ax"));
}

#[test]
fn nothing_close_gives_none() {
    assert_eq!(suggest("Chimney", RULES), None);
    assert_eq!(
        suggest("A", ["B"]),
        None,
        "replacing every character is no suggestion"
    );
    assert_eq!(suggest("Door", RULES), None);
    assert_eq!(suggest("x", std::iter::empty()), None);
    assert_eq!(suggest("", ["A"]), None);
}

#[test]
fn an_exact_match_is_the_closest() {
    assert_eq!(suggest("Wall", RULES), Some("Wall"));
}

#[test]
fn multi_byte_names() {
    assert_eq!(suggest("Fassäde", ["Fassade", "Dach"]), Some("Fassade"));
}

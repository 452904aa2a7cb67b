//! Split sizes follow CGA: absolute, relative, floating, repeats, and what does not fit.

use crate::common;

use common::{lot, names, run};
use shapegram_eval::Derivation;

/// The x positions and sizes of the leaves.
fn spans(d: &Derivation) -> Vec<(f64, f64)> {
    d.leaves
        .iter()
        .map(|l| (round(l.scope.origin.x), round(l.scope.size.x)))
        .collect()
}

fn round(v: f64) -> f64 {
    (v * 1e9).round() / 1e9
}

fn split_x(block: &str) -> Derivation {
    let grammar = format!("Lot --> s(5, 1, 1) primitiveCube() split(x) {block}");
    run(&grammar, lot(10.0, 10.0))
}

#[test]
fn absolute_sizes_leave_the_rest_empty() {
    let d = split_x("{ 3 : Green | 1 : Blue }");
    assert_eq!(names(&d), ["Green", "Blue"]);
    assert_eq!(spans(&d), [(0.0, 3.0), (3.0, 1.0)]);
}

#[test]
fn parts_past_the_end_are_cut_or_dropped() {
    let d = split_x("{ 2 : A | 1 : B | 1 : C | 2 : Yellow | 1 : Dropped }");
    assert_eq!(names(&d), ["A", "B", "C", "Yellow"]);
    assert_eq!(spans(&d)[3], (4.0, 1.0));
}

#[test]
fn zero_and_negative_sizes_make_nothing_and_take_no_room() {
    let d = split_x("{ 1.5 : A | -2 : No | 1.5 : B | 1.5 : C | 0 : No | 1.5 : D }");
    assert_eq!(names(&d), ["A", "B", "C", "D"]);
    assert_eq!(spans(&d), [(0.0, 1.5), (1.5, 1.5), (3.0, 1.5), (4.5, 0.5)]);
}

#[test]
fn relative_and_floating_sizes() {
    let d = split_x("{ '0.2 : A | ~1 : B | 1 : C }");
    assert_eq!(spans(&d), [(0.0, 1.0), (1.0, 3.0), (4.0, 1.0)]);
    let d = split_x("{ 1 : A | ~2 : B | 1 : C | ~1 : D }");
    // The floating parts share 3 in the ratio 2 : 1.
    assert_eq!(spans(&d), [(0.0, 1.0), (1.0, 2.0), (3.0, 1.0), (4.0, 1.0)]);
    let d = split_x("{ 5 : A | ~1 : NoRoom }");
    assert_eq!(names(&d), ["A"]);
}

#[test]
fn repeats_fill_the_scope() {
    let run10 = |block: &str| {
        run(
            &format!("Lot --> s(10, 1, 1) primitiveCube() split(x) {block}"),
            lot(10.0, 10.0),
        )
    };
    assert_eq!(spans(&run10("{ 2 : A }*")).len(), 5);
    let floating = run10("{ ~2.1 : A }*");
    assert_eq!(spans(&floating).len(), 5);
    assert!(spans(&floating).iter().all(|&(_, s)| s == 2.0));
    // Absolute repeats leave what does not fit empty.
    let d = run10("{ 3 : A }*");
    assert_eq!(spans(&d), [(0.0, 3.0), (3.0, 3.0), (6.0, 3.0)]);
    // A repeated group between fixed parts, with split.index and split.total.
    let d = run(
        "Lot --> s(10, 1, 1) primitiveCube() split(x) { 1 : W | { ~2 : T(split.index, split.total) }* | 1 : W }
         T(i, n) --> s(1, 1, 1) Tile(i * 10 + n)",
        lot(10.0, 10.0),
    );
    assert_eq!(names(&d), ["W", "Tile", "Tile", "Tile", "Tile", "W"]);
    assert_eq!(
        spans(&d)[1..5].iter().map(|s| s.0).collect::<Vec<_>>(),
        [1.0, 3.0, 5.0, 7.0]
    );
}

#[test]
fn repeating_the_whole_block_and_nested_groups() {
    let d = run(
        "Lot --> s(12, 1, 1) primitiveCube() split(x) { ~1 : A | 2 : B }*",
        lot(10.0, 10.0),
    );
    assert_eq!(names(&d), ["A", "B", "A", "B", "A", "B", "A", "B"]);
    assert_eq!(spans(&d)[0], (0.0, 1.0));
    let d = run(
        "Lot --> s(10, 1, 1) primitiveCube() split(x) { 1 : A | { 1 : B | ~1 : C }* | 1 : A }",
        lot(10.0, 10.0),
    );
    assert_eq!(names(&d).len(), 2 + 8);
}

#[test]
fn splits_along_y_and_z_and_nested() {
    let d = run(
        "Lot --> s(4, 6, 8) primitiveCube() split(y) { 2 : split(z) { ~1 : A | ~1 : B } | ~1 : C }",
        lot(10.0, 10.0),
    );
    assert_eq!(names(&d), ["A", "B", "C"]);
    let sizes: Vec<[f64; 3]> = d.leaves.iter().map(|l| l.scope.size.to_array()).collect();
    assert_eq!(sizes, [[4.0, 2.0, 4.0], [4.0, 2.0, 4.0], [4.0, 4.0, 8.0]]);
    assert_eq!(d.leaves[1].scope.origin.z, 4.0);
    assert_eq!(d.leaves[2].scope.origin.y, 2.0);
}

#[test]
fn a_huge_repeat_is_an_error_not_a_hang() {
    let err = common::try_run(
        "Lot --> s(1000, 1, 1) primitiveCube() split(x) { 0.00001 : A }*",
        lot(10.0, 10.0),
        &Default::default(),
    )
    .unwrap_err();
    assert!(err.message.contains("limit is 1000000"), "{}", err.message);
    assert!(err.span.is_some());
}

#[test]
fn a_repeat_makes_the_parts_closest_to_their_size() {
    // 2.45 m of `~1` parts: two would be 1.225 m, three 0.8167 m, nearer 1 m.
    let d = run(
        "Lot --> s(2.45, 1, 1) primitiveCube() split(x) { ~1 : A }*",
        lot(10.0, 10.0),
    );
    assert_eq!(names(&d), ["A", "A", "A"]);
    assert_eq!(round(spans(&d)[0].1), round(2.45 / 3.0));
}

#[test]
fn a_floating_part_after_a_repeat_can_leave_it_out() {
    // Windows and dividers with a last window: where one window fills the tile the repeat
    // makes nothing; where three fit better than two (0.55 m against 0.72 m nominal, rather
    // than 0.95 m), it repeats twice.
    let windows = |width: f64, window: f64| {
        run(
            &format!(
                "Lot --> s({width}, 1, 1) primitiveCube() \
                 split(x) {{ {{ ~{window} : W | 0.25 : D }}* | ~{window} : W }}"
            ),
            lot(10.0, 10.0),
        )
    };
    let one = windows(2.15, 2.15);
    assert_eq!(names(&one), ["W"]);
    assert_eq!(spans(&one), [(0.0, 2.15)]);
    let three = windows(2.15, 0.72);
    assert_eq!(names(&three), ["W", "D", "W", "D", "W"]);
    assert_eq!(
        spans(&three),
        [
            (0.0, 0.55),
            (0.55, 0.25),
            (0.8, 0.55),
            (1.35, 0.25),
            (1.6, 0.55)
        ]
    );
}

#[test]
fn two_repeats_take_their_shares_in_turn() {
    // 9 m between fixed parts for two repeats of `~2`: 4.5 m each would make two parts each
    // (four in all, 2.25 m); taken in turn, the first makes two and leaves 5 m to the second,
    // which makes three: five parts of 1.8 m, nearest 2 m.
    let d = run(
        "Lot --> s(12.35, 1, 1) primitiveCube() \
         split(x) { 1 : E | { ~2 : A }* | 1.35 : M | { ~2 : B }* | 1 : E }",
        lot(10.0, 10.0),
    );
    assert_eq!(names(&d), ["E", "A", "A", "M", "B", "B", "B", "E"]);
    assert!(
        spans(&d)[1..7]
            .iter()
            .filter(|s| s.1 != 1.35)
            .all(|s| s.1 == 1.8)
    );
}

/// Bays of different widths in turn, each split into tiles that split again: the layout of a
/// block of literal sizes is kept for the next split of that block at that length, and must
/// never stand in for another length or block.
const BAYS: &str = "
attr tileW = 2
Lot --> s(24, 1, 1) primitiveCube() split(x) { 6 : Bay | 4 : Bay | 6 : Bay | 8 : Bay }
Bay --> split(x) { { ~TILE : Tile }* }
Tile --> split(x) { ~1 : W. | 1 : G. | ~1 : W. }
";

#[test]
fn kept_layouts_agree_with_laying_out_afresh() {
    let kept = run(&BAYS.replace("TILE", "2"), lot(10.0, 10.0));
    // Sizes read from an attribute are laid out afresh at every split.
    let fresh = run(&BAYS.replace("TILE", "tileW"), lot(10.0, 10.0));
    let glass: Vec<(f64, f64)> = spans(&kept)
        .into_iter()
        .zip(names(&kept))
        .filter(|(_, n)| *n == "G")
        .map(|(s, _)| s)
        .collect();
    // 3 + 2 + 3 + 4 tiles of 2 m, a 1 m pane in the middle of each.
    let expected: Vec<(f64, f64)> = (0..12).map(|i| (2.0 * f64::from(i) + 0.5, 1.0)).collect();
    assert_eq!(glass, expected);
    assert_eq!(kept.leaves.len(), 36);
    assert_eq!(names(&kept), names(&fresh));
    assert_eq!(spans(&kept), spans(&fresh));
}

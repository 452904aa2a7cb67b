//! Rewriting with exact expected words: D0L, bracketed, stochastic, context-sensitive (with the
//! paper's bracket-aware example) and parametric systems (ABOP §1.10).

use shapegram_lsystem::{DeriveOptions, LSystem};

fn system(text: &str) -> LSystem {
    LSystem::parse(text).unwrap_or_else(|e| panic!("{}", e.render("test", text)))
}

/// The word after `n` steps.
fn word(text: &str, n: u32) -> String {
    let system = system(text);
    let options = DeriveOptions {
        iterations: Some(n),
        ..DeriveOptions::default()
    };
    system.word_text(&system.derive(&options).unwrap())
}

fn count(word: &str, c: char) -> usize {
    word.chars().filter(|&d| d == c).count()
}

#[test]
fn algae_word_lengths_are_fibonacci_numbers() {
    let algae = "axiom: a\na -> ab\nb -> a\n";
    assert_eq!(word(algae, 0), "a");
    assert_eq!(word(algae, 1), "ab");
    assert_eq!(word(algae, 2), "aba");
    assert_eq!(word(algae, 5), "abaababaabaab");
    let (mut a, mut b) = (1usize, 2usize);
    for n in 1..=25 {
        assert_eq!(word(algae, n).len(), b, "step {n}");
        (a, b) = (b, a + b);
    }
}

#[test]
fn koch_curves_have_exact_segment_counts() {
    // Quadratic Koch island (ABOP Figure 1.7a): each F becomes 8.
    let island = "angle: 90\naxiom: F-F-F-F\nF -> F-F+F+FF-F-F+F\n";
    // The paper's Figure 2 (ABOP Figure 1.9b-like): each F becomes 6.
    let figure2 = "axiom: F-F-F-F\nF -> FF-F-F-F-F\n";
    // ABOP Figure 1.9a: each F becomes 8, with seven turns.
    let figure19a = "axiom: F-F-F-F\nF -> FF-F-F-F-F-F+F\n";
    for n in 0..=5u32 {
        let island_word = word(island, n);
        assert_eq!(count(&island_word, 'F'), 4 * 8usize.pow(n));
        // Turns: 3 in the axiom, and every F adds 6 in each step.
        let turns = count(&island_word, '+') + count(&island_word, '-');
        let expected_turns = 3 + (0..n).map(|k| 6 * 4 * 8usize.pow(k)).sum::<usize>();
        assert_eq!(turns, expected_turns, "step {n}");
        assert_eq!(count(&word(figure2, n), 'F'), 4 * 6usize.pow(n));
        assert_eq!(count(&word(figure19a, n), 'F'), 4 * 8usize.pow(n));
    }
    assert_eq!(
        word(island, 1),
        "F-F+F+FF-F-F+F-F-F+F+FF-F-F+F-F-F+F+FF-F-F+F-F-F+F+FF-F-F+F"
    );
}

#[test]
fn bracketed_plant_of_the_paper() {
    // The paper's Figure 3: ω: F, δ = 22.5°, F → FF-[-F+F+F]+[+F-F-F].
    let plant = "angle: 22.5\naxiom: F\nF -> FF-[-F+F+F]+[+F-F-F]\n";
    assert_eq!(word(plant, 1), "FF-[-F+F+F]+[+F-F-F]");
    let w = word(plant, 4);
    assert_eq!(count(&w, 'F'), 8usize.pow(4));
    assert_eq!(count(&w, '['), count(&w, ']'));
    assert_eq!(count(&w, '['), 2 * (1 + 8 + 64 + 512));
}

#[test]
fn signal_propagates_with_a_left_context() {
    // The paper's example 3.2.2: b < a → b, b → a on baaaa.
    let signal = "axiom: baaaa\nb < a -> b\nb -> a\n";
    let words: Vec<String> = (0..=5).map(|n| word(signal, n)).collect();
    assert_eq!(
        words,
        ["baaaa", "abaaa", "aabaa", "aaaba", "aaaab", "aaaaa"]
    );
}

#[test]
fn context_rules_take_precedence_over_context_free_ones() {
    // The context-free rule comes first in the file, the context rule still wins where it matches.
    let text = "axiom: xaaa\na -> c\nx < a -> b\n";
    assert_eq!(word(text, 1), "xbcc");
}

#[test]
fn bracket_aware_context_of_the_paper() {
    // Example 3.2.3: ω = JFF[J]F[J[J[JF]F], p0: JFF < F > JJF → FJ. The F after [J] matches:
    // [J] is skipped on the left; on the right, nothing fits along the axis, so branch mode
    // enters [J[J, skips [JF] and finds F.
    // The word as printed has an unclosed branch; closed, it derives the same.
    let text = "axiom: JFF[J]F[J[J[JF]F]\nJFF < F > JJF -> FJ\n";
    assert_eq!(word(text, 1), "JFF[J]FJ[J[J[JF]F]");
    let text = "axiom: JFF[J]F[J[J[JF]F]]\nJFF < F > JJF -> FJ\n";
    assert_eq!(word(text, 1), "JFF[J]FJ[J[J[JF]F]]");
    // Only that F: with a G instead of the last F, the right context fails.
    let text = "axiom: JFF[J]F[J[J[JF]G]]\nJFF < F > JJF -> FJ\n";
    assert_eq!(word(text, 1), "JFF[J]F[J[J[JF]G]]");
}

#[test]
fn abop_bracketed_context_example() {
    // ABOP §1.8: BC < S > G[H]M applies to S in ABC[DE][SG[HI[JK]L]MNO].
    let text = "axiom: ABC[DE][SG[HI[JK]L]MNO]\nBC < S > G[H]M -> X\n";
    assert_eq!(word(text, 1), "ABC[DE][XG[HI[JK]L]MNO]");
    // Without the branch in the word, the right context fails.
    let text = "axiom: ABC[DE][SGMNO][H]\nBC < S > G[H]M -> X\n";
    assert_eq!(word(text, 1), "ABC[DE][SGMNO][H]");
    // A right context never reaches past the end of its branch.
    let text = "axiom: A[B]C\nB > C -> X\n";
    assert_eq!(word(text, 1), "A[B]C");
}

#[test]
fn right_contexts_follow_the_axis_before_entering_branches() {
    // Along the axis, the right neighbour of A in A[B]C is C, whatever the production order.
    let text = "axiom: A[B]C\nA > B -> X\nA > C -> Y\n";
    assert_eq!(word(text, 1), "Y[B]C");
    let text = "axiom: A[B]C\nA > C -> Y\nA > B -> X\n";
    assert_eq!(word(text, 1), "Y[B]C");
    // When nothing matches along the axis, the branch is entered (the paper's reading).
    let text = "axiom: A[B]C\nA > B -> X\n";
    assert_eq!(word(text, 1), "X[B]C");
    // A context-free production yields to a context-sensitive one that matches only in branch
    // mode, and applies where none matches at all.
    let text = "axiom: A[B]CA\nA -> Z\nA > B -> X\n";
    assert_eq!(word(text, 1), "X[B]CZ");
}

#[test]
fn ignored_symbols_are_skipped_when_matching_contexts() {
    let text = "ignore: +-\naxiom: a+-b-c\na < b > c -> X\n";
    assert_eq!(word(text, 1), "a+-X-c");
    let text = "axiom: a+-b-c\na < b > c -> X\n";
    assert_eq!(word(text, 1), "a+-b-c");
}

#[test]
fn parametric_example_of_abop_section_1_10() {
    let text = "\
axiom: B(2)A(4,4)
A(x,y) : y <= 3 -> A(x*2, x+y)
A(x,y) : y > 3 -> B(x)A(x/y, 0)
B(x) : x < 1 -> C
B(x) : x >= 1 -> B(x-1)
";
    let words: Vec<String> = (0..=5).map(|n| word(text, n)).collect();
    assert_eq!(
        words,
        [
            "B(2)A(4,4)",
            "B(1)B(4)A(1,0)",
            "B(0)B(3)A(2,1)",
            "CB(2)A(4,3)",
            "CB(1)A(8,7)",
            "CB(0)B(8)A(1.1428571428571428,0)",
        ]
    );
}

#[test]
fn parametric_contexts_bind_their_parameters() {
    // Each A takes the sum of its own value and its left neighbour's.
    let text = "axiom: A(1)A(2)A(3)\nA(l) < A(x) -> A(x+l)\n";
    assert_eq!(word(text, 1), "A(1)A(3)A(5)");
    assert_eq!(word(text, 2), "A(1)A(4)A(8)");
}

#[test]
fn defines_and_labels() {
    let text = "define: r = 1.5\ndefine: s = r * 2\naxiom: A(s)\np1: A(x) -> A(x * r)B\n";
    assert_eq!(word(text, 2), "A(6.75)BB");
}

#[test]
fn numbers_print_in_shortest_round_trip_form() {
    let text = "axiom: A(0.1, -0, 1e20, 1e21, 0.30000000000000004, 0.000001, 1e-300, -2.5e-7)\n";
    let printed = word(text, 0);
    assert_eq!(
        printed,
        "A(0.1,0,100000000000000000000,1e21,0.30000000000000004,0.000001,1e-300,-2.5e-7)"
    );
    // What is printed reads back as the same word.
    assert_eq!(word(&format!("axiom: {printed}\n"), 0), printed);
}

/// The successor chosen for each of the 10,000 A's of a word after one step.
fn stochastic_word(seed: u64) -> String {
    let text = format!(
        "seed: {seed}\naxiom: {}\nA (1) -> x\nA (2) -> y\nA (1) -> z\n",
        "A".repeat(10_000)
    );
    word(&text, 1)
}

#[test]
fn alternatives_are_grouped_by_their_left_side_whatever_the_parameter_names() {
    let text = format!(
        "axiom: {}\nA(x) (1) : x > 0 -> B\nA(y) (1) : y > 0 -> C\nA(z) : z < 0 -> D\n",
        "A(1)".repeat(1000)
    );
    let derived = word(&text, 1);
    let (b, c) = (derived.matches('B').count(), derived.matches('C').count());
    assert_eq!((b + c, derived.matches('D').count()), (1000, 0));
    assert!((400..=600).contains(&b), "{b} of 1000 chose B");
    // Two unweighted productions differing only in parameter names are one left side twice.
    let err = LSystem::parse("axiom: A(1)\nA(x) -> B\nA(y) -> C\n").unwrap_err();
    assert_eq!(
        err.to_string(),
        "3:1: another production with the same left side is on line 2: give each alternative a weight, as in `A (0.5) -> …`"
    );
}

#[test]
fn stochastic_choices_are_deterministic_per_seed() {
    assert_eq!(stochastic_word(1), stochastic_word(1));
    assert_ne!(stochastic_word(1), stochastic_word(2));
    let options = DeriveOptions {
        seed: Some(9),
        ..DeriveOptions::default()
    };
    let plant = system(
        "angle: 30\nn: 5\naxiom: F\nF (0.33) -> F[+F]F[-F]F\nF (0.33) -> F[+F]F\nF (0.34) -> F[-F]F\n",
    );
    let a = plant.derive(&options).unwrap();
    let b = plant.derive(&options).unwrap();
    assert_eq!(a, b);
}

#[test]
fn stochastic_frequencies_follow_the_weights() {
    let mut counts = [0usize; 3];
    for seed in 0..20 {
        let w = stochastic_word(seed);
        counts[0] += count(&w, 'x');
        counts[1] += count(&w, 'y');
        counts[2] += count(&w, 'z');
    }
    let total: usize = counts.iter().sum();
    assert_eq!(total, 200_000);
    let share = |c: usize| c as f64 / total as f64;
    // Standard deviation of a share near 0.25 over 200,000 draws is about 0.001.
    assert!((share(counts[0]) - 0.25).abs() < 0.005, "{counts:?}");
    assert!((share(counts[1]) - 0.50).abs() < 0.005, "{counts:?}");
    assert!((share(counts[2]) - 0.25).abs() < 0.005, "{counts:?}");
}

#[test]
fn the_draw_of_a_module_depends_only_on_seed_step_and_position() {
    // Appending a deterministic tail does not change the choices made for the stochastic head.
    let head = word(
        "seed: 4\naxiom: AAAAAAAAAAAAAAAAAAAA\nA (1) -> x\nA (1) -> y\n",
        1,
    );
    let with_tail = word(
        "seed: 4\naxiom: AAAAAAAAAAAAAAAAAAAAQQ\nA (1) -> x\nA (1) -> y\nQ -> QQ\n",
        1,
    );
    assert_eq!(with_tail, format!("{head}QQQQ"));
}

#[test]
fn memory_limit_names_the_step_and_the_size() {
    let algae = system("axiom: a\na -> ab\nb -> a\n");
    let options = DeriveOptions {
        iterations: Some(40),
        max_modules: 1000,
        ..DeriveOptions::default()
    };
    let err = algae.derive(&options).unwrap_err();
    assert_eq!(
        err.to_string(),
        "step 15 would make a word of 1,597 modules, over the limit of 1,000 (raise the limit, or derive fewer steps)"
    );
    let none = DeriveOptions {
        max_modules: 0,
        ..options
    };
    assert_eq!(
        algae.derive(&none).unwrap_err().to_string(),
        "step 0 would make a word of 1 module, over the limit of 0 (raise the limit, or derive fewer steps)"
    );
    let parametric = system("axiom: A(1)\nA(x) -> A(x)A(x+1)\n");
    let err = parametric.derive(&options).unwrap_err();
    assert_eq!(
        err.to_string(),
        "step 10: the word grew past the limit of 1,000 modules after rewriting 501 of the 512 modules before it (raise the limit, or derive fewer steps)"
    );
}

#[test]
fn parameters_count_against_the_limit() {
    let wide = system("axiom: A(1,2,3,4)\nA(a,b,c,d) -> A(a,b,c,d)A(a,b,c,d)\n");
    let options = DeriveOptions {
        iterations: Some(20),
        max_modules: 1000,
        ..DeriveOptions::default()
    };
    let err = wide.derive(&options).unwrap_err();
    assert_eq!(
        err.to_string(),
        "step 8: the word's parameters grew past the limit of 1,000 values after rewriting 126 of the 128 modules before it (raise the module limit, or derive fewer steps)"
    );
}

/// The same productions, once as they are and once behind an always-true condition, which
/// forces the general engine instead of the D0L fast path: the words must agree.
fn fast_and_general(axiom: &str, productions: &[(char, String)], n: u32) -> (String, String) {
    let mut fast = format!("axiom: {axiom}\n");
    let mut general = fast.clone();
    for (pred, succ) in productions {
        fast.push_str(&format!("{pred} -> {succ}\n"));
        general.push_str(&format!("{pred} : 1 -> {succ}\n"));
    }
    (word(&fast, n), word(&general, n))
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(200))]

    #[test]
    fn d0l_fast_path_agrees_with_the_general_engine(
        axiom in "[AB+\\[\\]]{1,4}",
        a in "[AB+\\[\\]]{0,4}",
        b in "[AB+\\[\\]]{0,4}",
        n in 0u32..5,
    ) {
        let (fast, general) = fast_and_general(&axiom, &[('A', a), ('B', b)], n);
        proptest::prop_assert_eq!(fast, general);
    }
}

#[test]
fn pathological_context_searches_stop_with_an_error() {
    // Every A looks right across all the ignored A's after it: quadratic work.
    let text = format!("ignore: A\naxiom: {}B\nA > B -> C\n", "A".repeat(50_000));
    let err = system(&text).derive(&DeriveOptions::default()).unwrap_err();
    assert!(
        err.message
            .starts_with("step 1: matching contexts takes too long (at module "),
        "{err}"
    );
    // One module whose right context backtracks through every sibling branch, each time
    // running past all the others: quadratic work for a single search, stopped inside it.
    let text = format!(
        "axiom: X{}C\nX > [A]B -> Y\nC -> B\n",
        "[A]".repeat(100_000)
    );
    let err = system(&text).derive(&DeriveOptions::default()).unwrap_err();
    assert_eq!(
        err.message,
        "step 1: matching contexts takes too long (at module 0 of 300,002): the searches run through long runs of ignored symbols or of sibling branches, for many modules or for this one"
    );
}

#[test]
fn values_that_are_not_numbers_are_errors_with_places() {
    let zero = system("axiom: A(0)\nA(x) -> A(1/x)\n");
    let err = zero.derive(&DeriveOptions::default()).unwrap_err();
    assert_eq!(
        err.to_string(),
        "2:11: step 1: the parameter is inf, not a finite number, when rewriting A(0)"
    );
    let nan = system("axiom: A(-1)\nA(x) : sqrt(x) > 0 -> B\n");
    let err = nan.derive(&DeriveOptions::default()).unwrap_err();
    assert_eq!(
        err.to_string(),
        "2:8: step 1: the condition cannot be evaluated for A(-1) (it divides by zero, overflows or leaves a function's domain)"
    );
    // A division by zero makes no condition hold, whichever way it is compared.
    for condition in [
        "x/0 > 1",
        "x/0 < 1",
        "x/0",
        "!(x/0 == 0)",
        "x/0 > 1 || x > 0",
    ] {
        let text = format!("axiom: A(1)\nA(x) : {condition} -> B\n");
        let err = system(&text).derive(&DeriveOptions::default()).unwrap_err();
        assert!(
            err.to_string()
                .starts_with("2:8: step 1: the condition cannot be evaluated for A(1)"),
            "{condition}: {err}"
        );
    }
}

#[test]
fn cpfg_and_l_py_notation_paste_in() {
    let text = "\
#define R 2
#ignore: +-
Lsystem: 1
derivation length: 2
Axiom: A(1)+B
A(x) --> A(x*R)
B > A(x) --> C
A(x) < B --> D
endlsystem
";
    // The right context of B skips nothing (B is last); its left context skips the ignored +.
    assert_eq!(word(text, 1), "A(2)+D");
    let system = system(text);
    assert_eq!(system.settings.iterations, 2);
    assert_eq!(system.settings.ignore, ['+', '-']);
    let abop = "δ: 22.5\nω: F\np1: F → F[+F]F\n";
    assert_eq!(system_angle(abop), 22.5);
}

fn system_angle(text: &str) -> f64 {
    system(text).settings.angle
}

/// The left neighbour of every module along the path to the root, worked out forwards with a
/// stack (a different algorithm from the engine's backward search): `None` at the root, after
/// a `]` without partner, and for brackets and ignored symbols.
fn path_parents(word: &[char], ignored: char) -> Vec<Option<usize>> {
    const BROKEN: usize = usize::MAX;
    let mut parents = vec![None; word.len()];
    let mut last: Option<usize> = None;
    let mut stack = Vec::new();
    for (i, &c) in word.iter().enumerate() {
        match c {
            '[' => stack.push(last),
            ']' => last = stack.pop().unwrap_or(Some(BROKEN)),
            c if c == ignored => {}
            _ => {
                parents[i] = last.filter(|&p| p != BROKEN);
                last = Some(i);
            }
        }
    }
    parents
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(300))]

    /// `A B < C` rewrites exactly the C's whose path to the root reads B, then A.
    #[test]
    fn left_contexts_follow_the_path_to_the_root(word in "[ABC+\\[\\]]{1,24}") {
        // `A -> A` and `B -> B` put A and B into a successor, so the context is always valid.
        let text = format!("ignore: +\naxiom: {word}\nA B < C -> X\nA -> A\nB -> B\n");
        let derived = self::word(&text, 1);
        let chars: Vec<char> = word.chars().collect();
        let parents = path_parents(&chars, '+');
        let expected: String = chars
            .iter()
            .enumerate()
            .map(|(i, &c)| {
                let b = parents[i].filter(|&p| chars[p] == 'B');
                let a = b.and_then(|b| parents[b]).filter(|&p| chars[p] == 'A');
                if c == 'C' && a.is_some() { 'X' } else { c }
            })
            .collect();
        proptest::prop_assert_eq!(derived, expected);
    }
}

/// The positions a right context can continue at after reading up to `from`: the next module
/// along the axis or, entering branches, inside any branch that starts on the way (a plain
/// recursive definition of what the engine finds by backtracking).
fn right_candidates(word: &[char], partners: &[Option<usize>], from: usize, out: &mut Vec<usize>) {
    let mut i = from;
    while i < word.len() {
        match word[i] {
            '+' => i += 1,
            ']' => return,
            '[' => match partners[i] {
                Some(j) => {
                    right_candidates(word, partners, i + 1, out);
                    i = j + 1;
                }
                None => i += 1,
            },
            _ => {
                out.push(i);
                return;
            }
        }
    }
}

/// Whether `pattern` can be read to the right of `at` in any way (axis or branches).
fn right_matches(word: &[char], partners: &[Option<usize>], at: usize, pattern: &[char]) -> bool {
    let Some((&first, rest)) = pattern.split_first() else {
        return true;
    };
    let mut candidates = Vec::new();
    right_candidates(word, partners, at + 1, &mut candidates);
    candidates
        .into_iter()
        .any(|c| word[c] == first && right_matches(word, partners, c, rest))
}

fn bracket_partners(word: &[char]) -> Vec<Option<usize>> {
    let mut partners = vec![None; word.len()];
    let mut stack = Vec::new();
    for (i, &c) in word.iter().enumerate() {
        if c == '[' {
            stack.push(i);
        } else if c == ']'
            && let Some(j) = stack.pop()
        {
            partners[i] = Some(j);
            partners[j] = Some(i);
        }
    }
    partners
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(300))]

    /// With one production `C > A B`, a C is rewritten exactly when A B can be read to its
    /// right along the axis or, failing that, through branches.
    #[test]
    fn right_contexts_match_along_the_axis_or_through_branches(word in "[ABC+\\[\\]]{1,24}") {
        let text = format!("ignore: +\naxiom: {word}\nC > A B -> X\nA -> A\nB -> B\n");
        let derived = self::word(&text, 1);
        let chars: Vec<char> = word.chars().collect();
        let partners = bracket_partners(&chars);
        let expected: String = chars
            .iter()
            .enumerate()
            .map(|(i, &c)| {
                if c == 'C' && right_matches(&chars, &partners, i, &['A', 'B']) { 'X' } else { c }
            })
            .collect();
        proptest::prop_assert_eq!(derived, expected);
    }
}

#[test]
fn interpretation_rules_apply_once_before_drawing() {
    let text = "\
n: 2
axiom: A(1)
A(x) -> A(x+1)B
homomorphism:
A(x) -> F(x*2)[+F]
B -> F
";
    let system = system(text);
    let options = DeriveOptions::default();
    let word = system.derive(&options).unwrap();
    // The derivation itself does not see the interpretation rules.
    assert_eq!(system.word_text(&word), "A(3)BB");
    let shown = system.interpretation(&word, &options).unwrap();
    // Applied once: the F they produce is not rewritten again.
    assert_eq!(system.word_text(&shown), "F(6)[+F]FF");
    // Without interpretation rules, the word is drawn as it is.
    let plain = self::system("axiom: AB\n");
    let word = plain.derive(&options).unwrap();
    assert!(matches!(
        plain.interpretation(&word, &options).unwrap(),
        std::borrow::Cow::Borrowed(_)
    ));
    // Their errors name the interpretation.
    let failing = self::system("axiom: A(0)\ninterpretation:\nA(x) -> F(1/x)\n");
    let word = failing.derive(&options).unwrap();
    assert_eq!(
        failing
            .interpretation(&word, &options)
            .unwrap_err()
            .to_string(),
        "3:11: interpretation: the parameter is inf, not a finite number, when rewriting A(0)"
    );
}

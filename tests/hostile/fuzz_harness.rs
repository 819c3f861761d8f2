//! The fuzz engine (`examples/fuzz/engine.rs`) finds a planted bug: a test-only decoder that
//! panics on a magic byte sequence behind a header, found from a seed that does not contain
//! it within a bounded number of executions with a fixed RNG seed; and the engine's pieces
//! (bundles, PNG checksums, signatures) do what the fuzz binary relies on.

use crate::engine;

use engine::{Fuzzer, Outcome, Shape, Target, Verdict};

/// The planted bug: a "PLNT" container, version 1, then a payload that panics when it starts
/// with "BUG!". Each check refuses with its own message, as a real decoder's would: that is
/// the feedback the engine climbs.
fn planted(input: &[u8]) -> Outcome {
    if !input.starts_with(b"PLNT") {
        return Outcome::Refused("not a PLNT file (bad magic)".into());
    }
    if input.get(4) != Some(&1) {
        return Outcome::Refused("unsupported PLNT version".into());
    }
    let payload = &input[5..];
    for (i, &want) in b"BUG!".iter().enumerate() {
        match payload.get(i) {
            Some(&b) if b == want => {}
            Some(_) => {
                return Outcome::Refused(format!("payload byte {i} is not what it should be"));
            }
            None => return Outcome::Refused("payload too short".into()),
        }
        if i == 3 {
            panic!("planted bug reached");
        }
    }
    Outcome::Accepted("fine".into())
}

static PLANTED: Target = Target {
    name: "planted",
    about: "test-only: panics on PLNT v1 payloads starting with BUG!",
    execute: planted,
    shape: Shape::Binary,
    dictionary: &[],
    max_len: 64,
};

/// Executions within which the engine must find the planted bug. Measured: the fixed seed
/// finds it after 455 987 (0.2 s); the bound leaves room for changes to the mutator.
const BOUND: u64 = 2_000_000;

#[test]
fn the_engine_finds_a_planted_bug_within_a_bounded_number_of_executions() {
    std::panic::set_hook(Box::new(|_| {}));
    let seeds = vec![b"PLNT\x01....payload".to_vec()];
    let mut fuzzer = Fuzzer::new(&PLANTED, seeds, 20261203);
    let mut found = None;
    while fuzzer.executions < BOUND {
        let input = fuzzer.next_input();
        if let Verdict::Finding(finding) = fuzzer.execute(&input) {
            found = Some((fuzzer.executions, finding));
            break;
        }
    }
    let (executions, finding) = found.expect("the planted bug is found within the bound");
    eprintln!("planted bug found after {executions} executions");
    assert_eq!(finding.kind, "panic");
    assert!(
        finding.message.contains("planted bug"),
        "{}",
        finding.message
    );
    assert!(
        finding.input[5..].starts_with(b"BUG!"),
        "{:?}",
        finding.input
    );
}

#[test]
fn without_feedback_the_same_budget_finds_nothing() {
    // The control: the same loop with a target whose errors carry no information (one
    // message for every refusal) does not find the four bytes within the same bound; the
    // feedback is what finds them.
    fn opaque(input: &[u8]) -> Outcome {
        match planted(input) {
            Outcome::Refused(_) => Outcome::Refused("refused".into()),
            other => other,
        }
    }
    static OPAQUE: Target = Target {
        name: "opaque",
        about: "the planted decoder with one error message",
        execute: opaque,
        shape: Shape::Binary,
        dictionary: &[],
        max_len: 64,
    };
    std::panic::set_hook(Box::new(|_| {}));
    let mut fuzzer = Fuzzer::new(&OPAQUE, vec![b"PLNT\x01....payload".to_vec()], 20261203);
    let mut found = false;
    while fuzzer.executions < BOUND && !found {
        let input = fuzzer.next_input();
        found = matches!(fuzzer.execute(&input), Verdict::Finding(_));
    }
    assert!(
        !found,
        "a blind search found four exact bytes within the bound"
    );
}

#[test]
fn a_multi_line_or_empty_error_is_a_finding() {
    fn two_lines(_: &[u8]) -> Outcome {
        Outcome::Refused("first\nsecond".into())
    }
    static TWO: Target = Target {
        name: "two",
        about: "",
        execute: two_lines,
        shape: Shape::Binary,
        dictionary: &[],
        max_len: 8,
    };
    let mut fuzzer = Fuzzer::new(&TWO, vec![vec![0]], 1);
    match fuzzer.execute(b"x") {
        Verdict::Finding(f) => assert_eq!(f.kind, "contract"),
        Verdict::Clean => panic!("a two-line error passed"),
    }
}

#[test]
fn bundles_split_into_the_files_they_joined() {
    let main = br#"{"asset":{"version":"2.0"}}"#;
    let joined = engine::bundle::join(
        main,
        &[
            ("a b.bin".to_string(), &[0, 1, 2][..]),
            ("t.png".to_string(), &[][..]),
        ],
    );
    let (got, files) = engine::bundle::split(&joined);
    assert_eq!(got, main);
    assert_eq!(files.len(), 2);
    assert_eq!(files[0], ("a b.bin".to_string(), &[0u8, 1, 2][..]));
    assert_eq!(files[1].0, "t.png");
    assert!(engine::bundle::split(main).1.is_empty());
}

#[test]
fn png_checksums_are_recomputed_and_the_signature_ignores_numbers() {
    // CRC-32 of "IEND" is the constant every PNG ends with.
    assert_eq!(engine::crc32(b"IEND"), 0xae42_6082);
    let mut png = b"\x89PNG\r\n\x1a\n\0\0\0\0IEND\0\0\0\0".to_vec();
    engine::fix_png_crcs(&mut png);
    assert_eq!(&png[16..], &0xae42_6082u32.to_be_bytes());
    assert_eq!(
        engine::signature(b'R', "offset 17 past 20"),
        engine::signature(b'R', "offset 170 past 25")
    );
    assert_ne!(
        engine::signature(b'R', "offset 17"),
        engine::signature(b'R', "length 17")
    );
    assert_ne!(
        engine::signature(b'R', "byte 1 is wrong"),
        engine::signature(b'R', "byte 2 is wrong")
    );
}

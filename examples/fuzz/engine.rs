//! The in-process fuzz engine: a corpus, a mutator and one loop that calls a target function
//! over bytes, with panics caught. Shared by the fuzz binary (`examples/fuzz/main.rs`) and the
//! tests that check the engine itself (`tests/hostile/fuzz_harness.rs`).
//!
//! A *target* is a plain function from bytes to an [`Outcome`]. The engine keeps a corpus
//! (the seeds, then every input whose outcome had a *signature* not seen before: its result
//! summary or error message with the numbers of two or more digits blanked out) and makes each new input by
//! stacking one to four mutations of a corpus entry. The signature is cheap feedback without
//! compiler instrumentation (stable Rust has none for this): glint's errors name what was
//! wrong, so a new message means the input got further, or elsewhere, in the decoder; the
//! planted-bug test shows it climbing a four-byte magic one byte at a time.
//!
//! What counts as a finding: a panic (caught with `catch_unwind`), an error message that
//! breaks the contract (empty, or more than one line), and whatever the target itself calls
//! [`Outcome::Broken`]. Aborts, hangs and allocations above the cap end or stop the process
//! and are found by the binary's watchdog and supervisor, not here.

#![allow(dead_code)] // The binary and the tests use different parts.

use rand::{Rng, RngCore, SeedableRng};
use std::collections::HashSet;

/// What one execution of a target gave.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// The input was accepted; the text summarises the result (it feeds the signature).
    Accepted(String),
    /// The input was refused with this error message (one line, naming what was wrong).
    Refused(String),
    /// A breach of the target's contract that is not a panic (described).
    Broken(String),
}

/// How the mutator sees a target's inputs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shape {
    /// Opaque bytes.
    Binary,
    /// Text (TOML): numbers are replaced by hostile ones, lines duplicated.
    Text,
    /// A glTF bundle ([`bundle`]): JSON edits of the `.gltf` text or `.glb` JSON chunk, byte
    /// damage elsewhere.
    Gltf,
}

/// A fuzz target.
pub struct Target {
    /// The name on the command line and in file names.
    pub name: &'static str,
    /// One line about what it reaches.
    pub about: &'static str,
    /// The function under test.
    pub execute: fn(&[u8]) -> Outcome,
    /// How inputs are mutated.
    pub shape: Shape,
    /// Tokens worth inserting (keywords, magic numbers).
    pub dictionary: &'static [&'static [u8]],
    /// Mutants are cut to this length.
    pub max_len: usize,
}

/// A finding: the input and why it is one.
#[derive(Clone, Debug)]
pub struct Finding {
    /// `panic` or `contract`.
    pub kind: &'static str,
    /// The panic message or the broken contract.
    pub message: String,
    /// The input.
    pub input: Vec<u8>,
}

/// What [`Fuzzer::execute`] decided.
#[derive(Clone, Debug)]
pub enum Verdict {
    /// Accepted or refused as the contract allows.
    Clean,
    /// A panic or a breach.
    Finding(Finding),
}

/// The corpus is not grown past this many entries (the seeds always stay).
const MAX_CORPUS: usize = 4096;

/// The engine's state for one target.
pub struct Fuzzer<'t> {
    target: &'t Target,
    corpus: Vec<Vec<u8>>,
    /// Indices into `corpus` of the seeds and of kept inputs that were accepted.
    valid: Vec<usize>,
    seen: HashSet<u64>,
    rng: rand_pcg::Pcg64,
    /// Executions so far.
    pub executions: u64,
    /// Of which accepted.
    pub accepted: u64,
    /// Findings so far.
    pub findings: u64,
}

impl<'t> Fuzzer<'t> {
    /// A fuzzer over `seeds` (an empty list starts from one empty input), seeded with
    /// `rng_seed`: the same seed, seeds and target give the same inputs.
    pub fn new(target: &'t Target, seeds: Vec<Vec<u8>>, rng_seed: u64) -> Self {
        let mut corpus: Vec<Vec<u8>> = seeds
            .into_iter()
            .map(|mut s| {
                s.truncate(target.max_len);
                s
            })
            .collect();
        if corpus.is_empty() {
            corpus.push(Vec::new());
        }
        Self {
            target,
            valid: (0..corpus.len()).collect(),
            corpus,
            seen: HashSet::new(),
            rng: rand_pcg::Pcg64::seed_from_u64(rng_seed),
            executions: 0,
            accepted: 0,
            findings: 0,
        }
    }

    /// The corpus size (seeds and kept inputs).
    pub fn corpus_len(&self) -> usize {
        self.corpus.len()
    }

    /// The next input: a corpus entry, mutated. Half the time the entry is a seed or an
    /// accepted input (most refused inputs are refused early, and their mutants too), a
    /// quarter of the time one of the eight newest entries.
    pub fn next_input(&mut self) -> Vec<u8> {
        let pick = match self.rng.random_range(0..4) {
            0 | 1 => self.valid[self.rng.random_range(0..self.valid.len())],
            // The newest entries: what got furthest most recently.
            2 => self.corpus.len() - 1 - self.rng.random_range(0..self.corpus.len().min(8)),
            _ => self.rng.random_range(0..self.corpus.len()),
        };
        let other = self.rng.random_range(0..self.corpus.len());
        let mut input = self.corpus[pick].clone();
        if self.target.shape == Shape::Gltf && self.rng.random_bool(0.6) {
            // JSON edits alone: byte damage on top would mostly break the JSON.
            input = mutate_bundle(&input, &mut self.rng);
        } else {
            let rounds = match self.rng.random_range(0..4) {
                0 | 1 => 1,
                2 => 2,
                _ => 4,
            };
            for _ in 0..rounds {
                mutate_bytes(
                    &mut input,
                    &self.corpus[other],
                    self.target.shape,
                    self.target.dictionary,
                    &mut self.rng,
                );
            }
        }
        if self.rng.random_bool(0.9) {
            fix_png_crcs(&mut input);
        }
        input.truncate(self.target.max_len);
        input
    }

    /// Runs the target on `input` with panics caught, checks the contract and keeps the input
    /// when its signature is new.
    pub fn execute(&mut self, input: &[u8]) -> Verdict {
        self.executions += 1;
        let run = std::panic::catch_unwind(|| (self.target.execute)(input));
        let finding = |kind, message: String| {
            Verdict::Finding(Finding {
                kind,
                message,
                input: input.to_vec(),
            })
        };
        let verdict = match &run {
            Err(payload) => finding("panic", panic_text(payload.as_ref())),
            Ok(Outcome::Broken(why)) => finding("contract", why.clone()),
            Ok(Outcome::Refused(message)) if message.trim().is_empty() => {
                finding("contract", "an empty error message".into())
            }
            Ok(Outcome::Refused(message)) if message.contains('\n') => {
                finding("contract", format!("a multi-line error: {message}"))
            }
            Ok(_) => Verdict::Clean,
        };
        match &run {
            Ok(Outcome::Accepted(summary)) => {
                self.accepted += 1;
                self.keep_if_new(b'A', summary, input);
            }
            Ok(Outcome::Refused(message)) => self.keep_if_new(b'R', message, input),
            _ => {}
        }
        if matches!(verdict, Verdict::Finding(_)) {
            self.findings += 1;
        }
        verdict
    }

    fn keep_if_new(&mut self, tag: u8, text: &str, input: &[u8]) {
        let signature = signature(tag, text);
        if self.seen.insert(signature) && self.corpus.len() < MAX_CORPUS {
            if tag == b'A' {
                self.valid.push(self.corpus.len());
            }
            self.corpus.push(input.to_vec());
        }
    }
}

/// The text of a panic payload.
pub fn panic_text(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<String>()
        .cloned()
        .or_else(|| payload.downcast_ref::<&str>().map(|s| s.to_string()))
        .unwrap_or_else(|| "a panic with a non-text payload".into())
}

/// A hash of `text` with every number of two or more digits blanked, so that "offset 17" and
/// "offset 18" are one signature and "offset 17" and "length 17" are two. Single digits are
/// kept: they are mostly indices of fields, channels, bytes or versions, where a different
/// digit means the input got somewhere else.
pub fn signature(tag: u8, text: &str) -> u64 {
    let mut shape = Vec::with_capacity(text.len() + 1);
    shape.push(tag);
    let bytes = text.as_bytes();
    let bytes = &bytes[..bytes.len().min(512)];
    let mut i = 0;
    while i < bytes.len() {
        let run = bytes[i..].iter().take_while(|b| b.is_ascii_digit()).count();
        match run {
            0 => {
                shape.push(bytes[i]);
                i += 1;
            }
            1 => {
                shape.push(bytes[i]);
                i += 1;
            }
            _ => {
                shape.push(b'#');
                i += run;
            }
        }
    }
    xxhash_rust::xxh3::xxh3_64(&shape)
}

/// Values that break size arithmetic, written as integers of 1, 2, 4 or 8 bytes.
const INTERESTING: &[u64] = &[
    0,
    1,
    2,
    3,
    4,
    7,
    8,
    16,
    32,
    64,
    127,
    128,
    255,
    256,
    1023,
    1024,
    4095,
    4096,
    32767,
    32768,
    65535,
    65536,
    0x7fff_ffff,
    0x8000_0000,
    0xffff_ffff,
    0x1_0000_0000,
    0x7fff_ffff_ffff_ffff,
    u64::MAX,
];

/// Decimal numbers that break parsers' and checkers' arithmetic, for text inputs.
const TEXT_NUMBERS: &[&str] = &[
    "0",
    "-1",
    "1",
    "2",
    "3",
    "-0",
    "0.5",
    "1e39",
    "-1e39",
    "1e308",
    "nan",
    "inf",
    "-inf",
    "65536",
    "4294967295",
    "4294967296",
    "9223372036854775807",
    "18446744073709551616",
    "1000000000",
    "99999",
    "16777217",
];

/// One to several byte-level edits of `input` (`other`: a second corpus entry to splice).
pub fn mutate_bytes(
    input: &mut Vec<u8>,
    other: &[u8],
    shape: Shape,
    dictionary: &[&[u8]],
    rng: &mut impl RngCore,
) {
    let len = input.len();
    let at = |rng: &mut dyn RngCore, len: usize| {
        if len == 0 {
            0
        } else if rng.random_bool(0.5) {
            // Headers come first: aim half of the edits at the first 64 bytes.
            rng.random_range(0..len.min(64))
        } else {
            rng.random_range(0..len)
        }
    };
    let choice = rng.random_range(0..16);
    match choice {
        0 | 1 if len > 0 => {
            let i = at(rng, len);
            input[i] ^= 1 << rng.random_range(0..8);
        }
        2 if len > 0 => {
            let i = at(rng, len);
            // Printable ASCII half of the time: magic numbers and keywords are mostly text.
            input[i] = if rng.random_bool(0.5) {
                rng.random_range(0x20..0x7f)
            } else {
                rng.random()
            };
        }
        3 | 4 if len > 0 => {
            // An interesting integer, 1/2/4/8 bytes, little or big endian.
            let value = INTERESTING[rng.random_range(0..INTERESTING.len())];
            let width = 1 << rng.random_range(0..4);
            let bytes = if rng.random_bool(0.75) {
                value.to_le_bytes()
            } else {
                value.to_be_bytes()
            };
            let bytes = if bytes[0] == 0 && width < 8 && rng.random_bool(0.5) {
                &bytes[8 - width..]
            } else {
                &bytes[..width]
            };
            let i = at(rng, len);
            let end = (i + width).min(len);
            input[i..end].copy_from_slice(&bytes[..end - i]);
        }
        5 if len > 0 => {
            // A small step added to a little-endian u32.
            let i = at(rng, len);
            let end = (i + 4).min(len);
            let mut word = [0u8; 4];
            word[..end - i].copy_from_slice(&input[i..end]);
            let step = rng.random_range(-16i32..=16);
            let word = u32::from_le_bytes(word)
                .wrapping_add_signed(step)
                .to_le_bytes();
            input[i..end].copy_from_slice(&word[..end - i]);
        }
        6 if len > 0 => {
            // Delete a range.
            let i = rng.random_range(0..len);
            let n = rng.random_range(1..=(len - i).min(64));
            input.drain(i..i + n);
        }
        7 => {
            // Insert random bytes.
            let i = if len == 0 {
                0
            } else {
                rng.random_range(0..=len)
            };
            let n = rng.random_range(1..=16);
            let bytes: Vec<u8> = (0..n).map(|_| rng.random()).collect();
            input.splice(i..i, bytes);
        }
        8 if len > 0 => {
            // Duplicate a range in place.
            let i = rng.random_range(0..len);
            let n = rng.random_range(1..=(len - i).min(256));
            let chunk = input[i..i + n].to_vec();
            input.splice(i..i, chunk);
        }
        9 if len > 0 => {
            input.truncate(rng.random_range(0..len));
        }
        10 if !other.is_empty() => {
            // Splice: our prefix, the other's suffix.
            let cut = if len == 0 {
                0
            } else {
                rng.random_range(0..len)
            };
            let from = rng.random_range(0..other.len());
            input.truncate(cut);
            input.extend_from_slice(&other[from..]);
        }
        11 | 12 if !dictionary.is_empty() => {
            let token = dictionary[rng.random_range(0..dictionary.len())];
            let i = if len == 0 {
                0
            } else {
                rng.random_range(0..=len)
            };
            if rng.random_bool(0.5) || i + token.len() > len {
                input.splice(i..i, token.iter().copied());
            } else {
                input[i..i + token.len()].copy_from_slice(token);
            }
        }
        13 | 14 if shape != Shape::Binary => replace_number(input, rng),
        15 if shape == Shape::Text => duplicate_line(input, rng),
        _ if len > 0 => {
            let i = at(rng, len);
            input[i] = input[i].wrapping_add(rng.random_range(1..=4));
        }
        _ => input.push(rng.random()),
    }
}

/// Replaces one run of decimal digits (with its sign and fraction) by a hostile number.
fn replace_number(input: &mut Vec<u8>, rng: &mut impl RngCore) {
    let starts: Vec<usize> = (0..input.len())
        .filter(|&i| input[i].is_ascii_digit() && (i == 0 || !input[i - 1].is_ascii_digit()))
        .collect();
    if starts.is_empty() {
        return;
    }
    let mut start = starts[rng.random_range(0..starts.len())];
    if start > 0 && input[start - 1] == b'-' {
        start -= 1;
    }
    let mut end = start + 1;
    while end < input.len() && (input[end].is_ascii_digit() || matches!(input[end], b'.' | b'e')) {
        end += 1;
    }
    let number = TEXT_NUMBERS[rng.random_range(0..TEXT_NUMBERS.len())];
    input.splice(start..end, number.bytes());
}

/// Duplicates one line of a text input (a repeated key, table or array entry).
fn duplicate_line(input: &mut Vec<u8>, rng: &mut impl RngCore) {
    let starts: Vec<usize> = std::iter::once(0)
        .chain(
            (0..input.len())
                .filter(|&i| input[i] == b'\n')
                .map(|i| i + 1),
        )
        .filter(|&i| i < input.len())
        .collect();
    if starts.is_empty() {
        return;
    }
    let start = starts[rng.random_range(0..starts.len())];
    let end = input[start..]
        .iter()
        .position(|&b| b == b'\n')
        .map_or(input.len(), |n| start + n + 1);
    let line = input[start..end].to_vec();
    let times = rng.random_range(1..=8);
    for _ in 0..times {
        input.splice(start..start, line.iter().copied());
    }
}

/// A structure-aware edit of a glTF bundle's main file (JSON value edits; GLB chunk lengths
/// kept right), its companion files left as they are.
fn mutate_bundle(input: &[u8], rng: &mut impl RngCore) -> Vec<u8> {
    let (main, files) = bundle::split(input);
    let main = super::mutate::mutate(main, rng);
    bundle::join(&main, &files)
}

/// Recomputes every chunk CRC of a PNG so that mutations reach the chunk parsers instead of
/// stopping at the checksum. Anything that is not a PNG is left alone.
pub fn fix_png_crcs(bytes: &mut [u8]) {
    const MAGIC: &[u8] = b"\x89PNG\r\n\x1a\n";
    if !bytes.starts_with(MAGIC) {
        return;
    }
    let mut at = MAGIC.len();
    while at + 12 <= bytes.len() {
        let length = u32::from_be_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]]);
        let Some(end) = (at + 8).checked_add(length as usize) else {
            return;
        };
        if end + 4 > bytes.len() {
            return;
        }
        let crc = crc32(&bytes[at + 4..end]);
        bytes[end..end + 4].copy_from_slice(&crc.to_be_bytes());
        at = end + 4;
    }
}

/// CRC-32 (ISO-HDLC, PNG's), bit by bit: inputs are small.
pub fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in bytes {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = if crc & 1 != 0 {
                (crc >> 1) ^ 0xedb8_8320
            } else {
                crc >> 1
            };
        }
    }
    !crc
}

/// One input that holds a glTF file and the external files it names: the main file, then for
/// each external file [`MARK`], its relative path, a NUL and its bytes. An input without the
/// mark is a main file alone (a `.glb`, or a `.gltf` with data URIs).
pub mod bundle {
    /// Separates the files of a bundle.
    pub const MARK: &[u8] = b"\0\xffGLINT-FILE:";

    /// The main file and the (path, bytes) of each external file.
    pub fn split(input: &[u8]) -> (&[u8], Vec<(String, &[u8])>) {
        let mut parts = Vec::new();
        let mut rest = input;
        let mut main: Option<&[u8]> = None;
        loop {
            let found = rest.windows(MARK.len()).position(|w| w == MARK);
            let (part, next) = match found {
                Some(i) => (&rest[..i], Some(&rest[i + MARK.len()..])),
                None => (rest, None),
            };
            match main {
                None => main = Some(part),
                Some(_) => {
                    let nul = part.iter().position(|&b| b == 0).unwrap_or(part.len());
                    let name = String::from_utf8_lossy(&part[..nul]).into_owned();
                    let bytes = part.get(nul + 1..).unwrap_or(&[]);
                    parts.push((name, bytes));
                }
            }
            match next {
                Some(next) => rest = next,
                None => break,
            }
        }
        (main.unwrap_or(&[]), parts)
    }

    /// The bundle of `main` and `files`.
    pub fn join(main: &[u8], files: &[(String, &[u8])]) -> Vec<u8> {
        let mut out = main.to_vec();
        for (name, bytes) in files {
            out.extend_from_slice(MARK);
            out.extend_from_slice(name.as_bytes());
            out.push(0);
            out.extend_from_slice(bytes);
        }
        out
    }
}

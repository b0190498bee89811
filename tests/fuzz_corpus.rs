//! Replays the fuzz corpora (`fuzz/corpus/<target>/`, grown and minimised by cargo-fuzz) and every crash the
//! fuzzers found (`fuzz/regressions/<target>/`, minimised) through the same entry points as the fuzz targets,
//! on the stable toolchain: each input must come back without a panic.

use std::path::Path;

#[path = "common/place.rs"]
mod place;

type Target = fn(&[u8]);

const TARGETS: [(&str, Target); 4] = [
    ("gsf", diffract::fuzz::gsf),
    ("png_heightfield", diffract::fuzz::png_heightfield),
    ("obj", diffract::fuzz::obj),
    ("scene", diffract::fuzz::scene),
];

fn files(dir: &Path) -> Vec<std::path::PathBuf> {
    let Ok(entries) = std::fs::read_dir(dir) else { return Vec::new() };
    let mut files: Vec<_> = entries.map(|e| e.unwrap().path()).filter(|p| p.is_file()).collect();
    files.sort();
    files
}

#[test]
fn every_corpus_input_and_every_found_crash_is_handled() {
    let root = place::root().join("fuzz");
    let mut failures = Vec::new();
    for (name, target) in TARGETS {
        let corpus = files(&root.join("corpus").join(name));
        assert!(corpus.len() >= 5, "fuzz/corpus/{name} holds {} inputs: the corpus is missing", corpus.len());
        let regressions = files(&root.join("regressions").join(name));
        for path in corpus.iter().chain(&regressions) {
            let bytes = std::fs::read(path).unwrap();
            if std::panic::catch_unwind(|| target(&bytes)).is_err() {
                failures.push(path.display().to_string());
            }
        }
        println!("{name}: {} corpus inputs, {} regressions replayed", corpus.len(), regressions.len());
    }
    assert!(failures.is_empty(), "inputs that panic:\n{}", failures.join("\n"));
}

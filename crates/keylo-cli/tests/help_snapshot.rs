//! Every `keylo … --help` page, compared with the snapshot in `tests/help/`: moving a
//! command's arguments between files must not change what users see. After a deliberate
//! change, regenerate with `KEYLO_BLESS=1 cargo test -p keylo-cli --test help_snapshot`.

use std::path::{Path, PathBuf};
use std::process::Command;

fn help(words: &[String]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_keylo"))
        .args(words)
        .arg("--help")
        .env("COLUMNS", "100")
        .env_remove("KEYLO_LOG")
        .output()
        .expect("running keylo");
    assert!(out.status.success(), "keylo {words:?} --help failed");
    String::from_utf8(out.stdout).expect("--help is UTF-8")
}

/// The subcommands a help page lists under `Commands:` (`help` left out).
fn subcommands(page: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut inside = false;
    for line in page.lines() {
        if line == "Commands:" {
            inside = true;
            continue;
        }
        if inside {
            if line.is_empty() || !line.starts_with("  ") {
                break;
            }
            // A command's name is at two spaces; its wrapped text is further in.
            if line.as_bytes().get(2).is_some_and(|c| *c != b' ') {
                let name = line.split_whitespace().next().unwrap_or_default();
                if name != "help" {
                    out.push(name.to_string());
                }
            }
        }
    }
    out
}

fn snapshot_name(words: &[String]) -> String {
    if words.is_empty() {
        "keylo.txt".into()
    } else {
        format!("keylo-{}.txt", words.join("-"))
    }
}

#[test]
fn every_help_page_is_as_snapshotted() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/help");
    let bless = std::env::var_os("KEYLO_BLESS").is_some();
    let mut queue: Vec<Vec<String>> = vec![Vec::new()];
    let mut seen: Vec<PathBuf> = Vec::new();
    let mut differ = Vec::new();
    while let Some(words) = queue.pop() {
        let page = help(&words);
        for sub in subcommands(&page) {
            let mut next = words.clone();
            next.push(sub);
            queue.push(next);
        }
        let file = dir.join(snapshot_name(&words));
        if bless {
            std::fs::create_dir_all(&dir).unwrap();
            std::fs::write(&file, &page).unwrap();
        } else {
            let want = std::fs::read_to_string(&file).unwrap_or_default();
            if want != page {
                differ.push(format!("{}:\n{page}", file.display()));
            }
        }
        seen.push(file);
    }
    // A snapshot whose command is gone is stale.
    if !bless {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if !seen.contains(&path) {
                differ.push(format!("{}: no such command any more", path.display()));
            }
        }
    }
    assert!(seen.len() > 20, "only {} help pages found", seen.len());
    assert!(
        differ.is_empty(),
        "{} help page(s) differ from tests/help/ (KEYLO_BLESS=1 after a deliberate change):\n{}",
        differ.len(),
        differ.join("\n")
    );
}

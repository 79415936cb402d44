//! Issue 37, parts A and B: a campaign folder never lies (its identity in
//! every part, `merge` checking every file once in its part, a part whole
//! across its tables, a failed merge leaving no manifest, another
//! campaign's folder refused before any work, only enginedyn's own parts
//! replaced, one file one row, options and engine compared by meaning),
//! and provenance by BLAKE3 in the pass that reads each diagram.

use arrow_array::{Array, RecordBatch, StringArray};
use enginedyn_tests::{binary, data};
use parquet::arrow::ArrowWriter;
use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;
use parquet::file::properties::WriterProperties;
use std::path::{Path, PathBuf};
use std::process::Output;

fn run(args: &[&str]) -> Output {
    std::process::Command::new(binary())
        .args(args)
        .output()
        .expect("run enginedyn")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn s(p: &Path) -> &str {
    p.to_str().expect("a UTF-8 path")
}

/// `n` copies of the bundled diagram named `{stem}{k}.csv` in `dir`.
fn diagrams(dir: &Path, stem: &str, n: usize) -> Vec<PathBuf> {
    (0..n)
        .map(|k| {
            let p = dir.join(format!("{stem}{k}.csv"));
            std::fs::copy(data("vaz2108.csv"), &p).unwrap();
            p
        })
        .collect()
}

/// A list file naming `files`, one a line.
fn list(dir: &Path, name: &str, files: &[PathBuf]) -> PathBuf {
    let p = dir.join(name);
    let text: String = files.iter().map(|f| format!("{}\n", s(f))).collect();
    std::fs::write(&p, text).unwrap();
    p
}

/// `batch --parquet DIR --files-from LIST [--shard I/N] extra…`.
fn shard(out: &Path, list: &Path, shard: Option<&str>, extra: &[&str]) -> Output {
    let engine = data("vaz2108.toml");
    let mut args = vec![
        "batch",
        "--engine",
        &engine,
        "--files-from",
        s(list),
        "--parquet",
        s(out),
    ];
    if let Some(sh) = shard {
        args.extend(["--shard", sh]);
    }
    args.extend(extra);
    run(&args)
}

fn ok(o: Output) -> Output {
    assert!(o.status.success(), "{}", stderr(&o));
    o
}

fn merge(out: &Path) -> Output {
    run(&["merge", s(out)])
}

fn part(out: &Path, table: &str, i: usize, n: usize) -> PathBuf {
    out.join(table)
        .join(format!("part-{i:05}-of-{n:05}.parquet"))
}

/// A string column of a part.
fn column(path: &Path, name: &str) -> Vec<Option<String>> {
    let b = ParquetRecordBatchReaderBuilder::try_new(std::fs::File::open(path).unwrap()).unwrap();
    let mut out = Vec::new();
    for batch in b.build().unwrap() {
        let batch = batch.unwrap();
        let c = batch.column_by_name(name).unwrap();
        let c = c.as_any().downcast_ref::<StringArray>().unwrap();
        out.extend((0..c.len()).map(|k| c.is_valid(k).then(|| c.value(k).to_string())));
    }
    out
}

/// Copies part `from` of table summary and cycles over part `to`.
fn copy_part(src: &Path, from: usize, dst: &Path, to: usize, n: usize) {
    for t in ["summary", "cycles"] {
        std::fs::copy(part(src, t, from, n), part(dst, t, to, n)).unwrap();
    }
}

#[test]
fn a_stale_shard_after_the_list_grew_fails_the_merge() {
    let t = tempfile::tempdir().unwrap();
    let files = diagrams(t.path(), "d", 6);
    let (old, out) = (t.path().join("old"), t.path().join("out"));
    let small = list(t.path(), "small.txt", &files[..4]);
    ok(shard(&old, &small, Some("0/2"), &[]));
    ok(shard(&old, &small, Some("1/2"), &[]));
    ok(merge(&old));
    // The list grows; only shard 1 runs again, beside shard 0 of before
    // (a scheduler that skipped a task it thought done).
    let big = list(t.path(), "big.txt", &files);
    ok(shard(&out, &big, Some("1/2"), &[]));
    copy_part(&old, 0, &out, 0, 2);
    let m = merge(&out);
    assert_eq!(m.status.code(), Some(1));
    let e = stderr(&m);
    assert!(
        e.contains(&format!(
            "{}: the file list differs from {}'s (list_blake3 ",
            part(&out, "summary", 1, 2).display(),
            part(&out, "summary", 0, 2).display()
        )),
        "{e}"
    );
    // A failed merge leaves no manifest vouching for the folder.
    assert!(!out.join("_manifest.json").exists());
}

#[test]
fn a_part_of_another_campaign_with_the_same_engine_and_options_fails() {
    let t = tempfile::tempdir().unwrap();
    let a = diagrams(t.path(), "a", 4);
    let b = diagrams(t.path(), "b", 4);
    let (out_a, out_b) = (t.path().join("A"), t.path().join("B"));
    let (la, lb) = (list(t.path(), "a.txt", &a), list(t.path(), "b.txt", &b));
    for (out, l) in [(&out_a, &la), (&out_b, &lb)] {
        ok(shard(out, l, Some("0/2"), &[]));
        ok(shard(out, l, Some("1/2"), &[]));
    }
    copy_part(&out_b, 1, &out_a, 1, 2);
    let m = merge(&out_a);
    assert_eq!(m.status.code(), Some(1));
    assert!(
        stderr(&m).contains(&format!(
            "{}: the file list differs from",
            part(&out_a, "summary", 1, 2).display()
        )),
        "{}",
        stderr(&m)
    );
}

#[test]
fn part_0_copied_over_part_2_fails_the_merge() {
    let t = tempfile::tempdir().unwrap();
    let files = diagrams(t.path(), "d", 3);
    let out = t.path().join("out");
    let l = list(t.path(), "l.txt", &files);
    for i in 0..3 {
        ok(shard(&out, &l, Some(&format!("{i}/3")), &[]));
    }
    ok(merge(&out));
    assert!(out.join("_manifest.json").exists());
    copy_part(&out, 0, &out, 2, 3);
    let m = merge(&out);
    assert_eq!(m.status.code(), Some(1));
    assert_eq!(
        stderr(&m).trim_end(),
        format!(
            "error: {}: its metadata says part 0 of 3, but its name says part 2 of 3: a copy of another part?",
            part(&out, "summary", 2, 3).display()
        )
    );
    // The earlier manifest is gone.
    assert!(!out.join("_manifest.json").exists());
}

#[test]
fn rows_doubled_fail_the_merge() {
    let t = tempfile::tempdir().unwrap();
    let files = diagrams(t.path(), "d", 2);
    let out = t.path().join("out");
    ok(shard(&out, &list(t.path(), "l.txt", &files), None, &[]));
    // Each row twice, the metadata kept (as a careless concatenation does).
    let p = part(&out, "summary", 0, 1);
    let b = ParquetRecordBatchReaderBuilder::try_new(std::fs::File::open(&p).unwrap()).unwrap();
    let kv = b.metadata().file_metadata().key_value_metadata().cloned();
    let schema = b.schema().clone();
    let batches: Vec<RecordBatch> = b.build().unwrap().map(Result::unwrap).collect();
    let props = WriterProperties::builder()
        .set_key_value_metadata(kv)
        .build();
    let mut w =
        ArrowWriter::try_new(std::fs::File::create(&p).unwrap(), schema, Some(props)).unwrap();
    for batch in batches.iter().chain(&batches) {
        w.write(batch).unwrap();
    }
    w.close().unwrap();
    let m = merge(&out);
    assert_eq!(m.status.code(), Some(1));
    assert_eq!(
        stderr(&m).trim_end(),
        format!(
            "error: {}: 4 rows for 2 files: rows added or doubled after it was written",
            p.display()
        )
    );
}

#[test]
fn merge_compares_options_and_engine_by_meaning() {
    let t = tempfile::tempdir().unwrap();
    let files = diagrams(t.path(), "d", 4);
    let out = t.path().join("out");
    let l = list(t.path(), "l.txt", &files);
    ok(shard(&out, &l, Some("0/2"), &[]));
    // The default step spelled out, and the engine file with a blank line more.
    let engine = t.path().join("engine.toml");
    let text = std::fs::read_to_string(data("vaz2108.toml")).unwrap();
    std::fs::write(&engine, format!("\n{text}")).unwrap();
    ok(run(&[
        "batch",
        "--engine",
        s(&engine),
        "--files-from",
        s(&l),
        "--parquet",
        s(&out),
        "--shard",
        "1/2",
        "--step",
        "0.1",
    ]));
    let m = ok(merge(&out));
    let manifest: serde_json::Value = serde_json::from_slice(&m.stdout).unwrap();
    assert_eq!(manifest["files"], 4);
    assert_eq!(manifest["parts"], 2);
}

#[test]
fn a_traces_shard_that_fails_mid_traces_leaves_no_part() {
    let t = tempfile::tempdir().unwrap();
    let files = diagrams(t.path(), "d", 2);
    let out = t.path().join("out");
    let l = list(t.path(), "l.txt", &files);
    // The third file written (summary, cycles, then traces) fails as a
    // full disk does.
    let engine = data("vaz2108.toml");
    let o = std::process::Command::new(binary())
        .args(["batch", "--engine", &engine, "--files-from", s(&l)])
        .args(["--parquet", s(&out), "--traces"])
        .env("ENGINEDYN_TEST_WRITE_FAIL", "3")
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    for table in ["summary", "cycles", "traces"] {
        assert!(!part(&out, table, 0, 1).exists(), "{table}");
    }
    assert_eq!(merge(&out).status.code(), Some(1));
    assert!(!out.join("_manifest.json").exists());
    // Nothing staged is left.
    let left: Vec<_> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .filter(|n| n.to_string_lossy().starts_with('.'))
        .collect();
    assert!(left.is_empty(), "{left:?}");
}

#[test]
fn a_folder_of_another_campaign_is_refused_before_any_work() {
    let t = tempfile::tempdir().unwrap();
    let a = diagrams(t.path(), "a", 2);
    let out = t.path().join("out");
    ok(shard(&out, &list(t.path(), "a.txt", &a), None, &[]));
    let before = std::fs::read(part(&out, "summary", 0, 1)).unwrap();
    // Another campaign: one of its files is missing, and no error about it
    // may be printed (the check comes before any work).
    let mut b = diagrams(t.path(), "b", 1);
    b.push(t.path().join("missing.csv"));
    let lb = list(t.path(), "b.txt", &b);
    let o = shard(&out, &lb, None, &[]);
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(
        e.starts_with(&format!(
            "error: --parquet {}: {}: holds a campaign of 1 part over the file list ",
            out.display(),
            part(&out, "summary", 0, 1).display()
        )) && e.contains(", not this one (a campaign of 1 part over the file list ")
            && e.contains("): the file list differs (list_blake3 ")
            && e.contains(" in this run); give --replace")
            && e.contains("give --replace (Python: overwrite=True)"),
        "{e}"
    );
    assert!(!e.contains("missing.csv"), "{e}");
    assert_eq!(std::fs::read(part(&out, "summary", 0, 1)).unwrap(), before);
    // --replace removes enginedyn's parts and writes this campaign.
    let o = ok(shard(&out, &lb, None, &["--replace"]));
    assert!(
        stderr(&o).contains(&format!(
            "note: parts of another campaign removed (--replace): {}, {}\n",
            part(&out, "summary", 0, 1).display(),
            part(&out, "cycles", 0, 1).display()
        )),
        "{}",
        stderr(&o)
    );
    let m = ok(merge(&out));
    let manifest: serde_json::Value = serde_json::from_slice(&m.stdout).unwrap();
    assert_eq!(
        (manifest["files"].as_u64(), manifest["failed"].as_u64()),
        (Some(2), Some(1))
    );
}

#[test]
fn a_users_file_at_a_parts_path_is_in_the_way() {
    let t = tempfile::tempdir().unwrap();
    let files = diagrams(t.path(), "d", 1);
    let out = t.path().join("out");
    let p = part(&out, "summary", 0, 1);
    std::fs::create_dir_all(p.parent().unwrap()).unwrap();
    std::fs::write(&p, "my notes").unwrap();
    let o = shard(&out, &list(t.path(), "l.txt", &files), None, &["--replace"]);
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(
        stderr(&o).trim_end(),
        format!(
            "error: --parquet {}: {}: a file without enginedyn's metadata is in the way of a part (only enginedyn's own parts are replaced): move it, or write the campaign to another folder",
            out.display(),
            p.display()
        )
    );
    assert_eq!(std::fs::read_to_string(&p).unwrap(), "my notes");
}

#[test]
fn a_killed_parts_staging_is_removed_by_the_next_run_of_that_part() {
    let t = tempfile::tempdir().unwrap();
    let files = diagrams(t.path(), "d", 2);
    let out = t.path().join("out");
    let mine = out.join(".enginedyn-part-00001-of-00002-x1y2z3");
    let other = out.join(".enginedyn-part-00000-of-00002-x1y2z3");
    for d in [&mine, &other] {
        std::fs::create_dir_all(d).unwrap();
        std::fs::write(d.join("summary"), "half").unwrap();
    }
    ok(shard(
        &out,
        &list(t.path(), "l.txt", &files),
        Some("1/2"),
        &[],
    ));
    assert!(!mine.exists());
    // Another part's staging is that part's to remove (it may be running).
    assert!(other.exists());
}

#[test]
fn one_file_one_row_by_canonical_path() {
    let t = tempfile::tempdir().unwrap();
    let dir = t.path().canonicalize().unwrap();
    diagrams(&dir, "a", 1);
    let abs = dir.join("a0.csv");
    let l = dir.join("l.txt");
    std::fs::write(&l, format!("a0.csv\n./a0.csv\n{}\n", s(&abs))).unwrap();
    let out = dir.join("out");
    let o = ok(shard(&out, &l, None, &[]));
    assert!(
        stderr(&o).contains(&format!(
            "note: 1 file named more than once, analysed once by its canonical path: {} as {}, {}\n",
            dir.join("a0.csv").display(),
            dir.join("./a0.csv").display(),
            abs.display()
        )),
        "{}",
        stderr(&o)
    );
    assert_eq!(
        column(&part(&out, "summary", 0, 1), "file"),
        vec![Some(s(&dir.join("a0.csv")).to_string())]
    );
}

#[test]
fn a_list_line_loses_only_its_line_end() {
    let t = tempfile::tempdir().unwrap();
    let p = t.path().join(" a.csv");
    std::fs::copy(data("vaz2108.csv"), &p).unwrap();
    let l = t.path().join("l.txt");
    std::fs::write(&l, " a.csv\r\n").unwrap();
    let out = t.path().join("out");
    ok(shard(&out, &l, None, &[]));
    let summary = part(&out, "summary", 0, 1);
    assert_eq!(column(&summary, "file"), vec![Some(s(&p).to_string())]);
    assert_eq!(column(&summary, "error"), vec![None]);
}

#[cfg(unix)]
#[test]
fn a_name_that_is_not_utf8_is_kept_escaped_and_never_collides() {
    use std::os::unix::ffi::OsStrExt;
    let t = tempfile::tempdir().unwrap();
    let dir = t.path();
    let raw = dir.join(std::ffi::OsStr::from_bytes(b"d\xff.csv"));
    let literal = dir.join("d\\xff.csv");
    for p in [&raw, &literal] {
        std::fs::copy(data("vaz2108.csv"), p).unwrap();
    }
    let l = dir.join("l.txt");
    let mut text = raw.as_os_str().as_bytes().to_vec();
    text.push(b'\n');
    text.extend_from_slice(literal.as_os_str().as_bytes());
    text.push(b'\n');
    std::fs::write(&l, text).unwrap();
    let out = dir.join("out");
    ok(shard(&out, &l, None, &[]));
    let summary = part(&out, "summary", 0, 1);
    let mut files: Vec<String> = column(&summary, "file").into_iter().flatten().collect();
    files.sort();
    let d = s(dir);
    assert_eq!(
        files,
        vec![format!("{d}/d\\x5cxff.csv"), format!("{d}/d\\xff.csv")]
    );
    assert_eq!(column(&summary, "error"), vec![None, None]);
    ok(merge(&out));
}

#[test]
fn each_diagram_is_hashed_with_blake3() {
    let t = tempfile::tempdir().unwrap();
    let files = diagrams(t.path(), "d", 2);
    std::fs::write(&files[1], "angle,pressure\n").unwrap();
    let out = t.path().join("out");
    let o = ok(shard(&out, &list(t.path(), "l.txt", &files), None, &[]));
    let want: Vec<Option<String>> = files
        .iter()
        .map(|f| {
            Some(
                blake3::hash(&std::fs::read(f).unwrap())
                    .to_hex()
                    .to_string(),
            )
        })
        .collect();
    let summary = part(&out, "summary", 0, 1);
    assert_eq!(column(&summary, "diagram_blake3"), want);
    drop(o);
    // The same in summary.json's `inputs` (batch --json).
    let engine = data("vaz2108.toml");
    let o = ok(run(&["batch", "--engine", &engine, "--json", s(&files[0])]));
    let rows: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(
        rows[0]["inputs"]["diagram_blake3"][0],
        want[0].clone().unwrap()
    );
    let engine_hash = blake3::hash(&std::fs::read(&engine).unwrap())
        .to_hex()
        .to_string();
    assert_eq!(rows[0]["inputs"]["engine_blake3"], engine_hash);
}

#[test]
fn quiet_and_notes_said_once_with_a_count() {
    let t = tempfile::tempdir().unwrap();
    // Four files: a kind of fewer than four is named, of more only counted.
    let files = diagrams(t.path(), "d", 4);
    let out = t.path().join("out");
    let l = list(t.path(), "l.txt", &files);
    let o = ok(shard(&out, &l, None, &[]));
    let e = stderr(&o);
    let counted: Vec<&str> = e
        .lines()
        .filter(|l| l.contains(": 4 of 4 files: "))
        .collect();
    assert!(!counted.is_empty(), "{e}");
    for f in &files {
        assert!(!e.contains(&format!("{}: ", f.display())), "{e}");
    }
    let o = ok(shard(&out, &l, None, &["--quiet"]));
    let e = stderr(&o);
    assert!(!e.lines().any(|l| l.starts_with("note:")), "{e}");
}

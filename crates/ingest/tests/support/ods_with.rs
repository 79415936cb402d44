//! The `.ods` fixture with rows of XML added after its header row: the
//! hostile sheets of `ods.rs`'s tests and of `tests/memory.rs` (one file,
//! included by both with `#[path]`).

use std::io::{Read, Write};

/// `libreoffice_cycles.ods` with `rows` (table rows' XML) added after its
/// header row, its parts deflated again.
pub fn ods_with(rows: &str) -> Vec<u8> {
    let src = std::fs::read(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../tests/fixtures/measured/libreoffice_cycles.ods"
    ))
    .unwrap();
    let mut zin = zip::ZipArchive::new(std::io::Cursor::new(&src)).unwrap();
    let mut out = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
    for i in 0..zin.len() {
        let mut f = zin.by_index(i).unwrap();
        let name = f.name().unwrap().to_string();
        let mut data = Vec::new();
        f.read_to_end(&mut data).unwrap();
        if name == "content.xml" {
            let text = String::from_utf8(data).unwrap();
            let end = "</table:table-row>";
            let at = text.find(end).unwrap() + end.len();
            data = format!("{}{rows}{}", &text[..at], &text[at..]).into_bytes();
        }
        let opts = zip::write::SimpleFileOptions::default()
            .compression_method(zip::CompressionMethod::Deflated);
        if name.ends_with('/') {
            out.add_directory(name, opts).unwrap();
        } else {
            out.start_file(name, opts).unwrap();
            out.write_all(&data).unwrap();
        }
    }
    out.finish().unwrap().into_inner()
}

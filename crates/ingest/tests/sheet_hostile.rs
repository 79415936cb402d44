//! The spreadsheet source's panic guard (issue 29, item 2): a panic inside
//! calamine on a damaged workbook is that file's error and prints nothing,
//! on any number of threads reading at once, while a panic anywhere else
//! still reaches the hook that was there before.

use enginedyn_ingest::{ParseOptions, parse};
use std::sync::atomic::{AtomicUsize, Ordering};

/// Panics the hook before ours was shown.
static SHOWN: AtomicUsize = AtomicUsize::new(0);

/// A .xls whose header no longer lists the FAT's second sector: calamine's
/// OLE reader (`cfb.rs`) indexes past the FAT it read, and panics.
fn damaged_xls() -> Vec<u8> {
    let mut xls = std::fs::read(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../tests/fixtures/measured/libreoffice_cycles.xls"
    ))
    .unwrap();
    assert_eq!(&xls[80..84], &128u32.to_le_bytes());
    xls[80..84].copy_from_slice(&u32::MAX.to_le_bytes());
    xls
}

// One test in this binary: the panic hook is the process's.
#[test]
fn a_panic_in_a_workbook_is_its_error_and_prints_nothing() {
    std::panic::set_hook(Box::new(|_| {
        SHOWN.fetch_add(1, Ordering::SeqCst);
    }));
    let xls = damaged_xls();
    let opts = ParseOptions::new(720.0);
    std::thread::scope(|s| {
        // Four readers of damaged workbooks at once, and beside them a
        // thread whose panics are none of theirs.
        for _ in 0..4 {
            s.spawn(|| {
                for _ in 0..25 {
                    let e = parse(std::io::Cursor::new(&xls), &opts).unwrap_err();
                    assert!(
                        e.to_string().starts_with("the spreadsheet is damaged"),
                        "{e}"
                    );
                }
            });
        }
        s.spawn(|| {
            for _ in 0..5 {
                assert!(std::panic::catch_unwind(|| panic!("elsewhere")).is_err());
                std::thread::yield_now();
            }
        });
    });
    assert_eq!(SHOWN.load(Ordering::SeqCst), 5);
    // A thread that read a workbook shows its own panics afterwards.
    assert!(parse(std::io::Cursor::new(&xls), &opts).is_err());
    assert!(std::panic::catch_unwind(|| panic!("after")).is_err());
    assert_eq!(SHOWN.load(Ordering::SeqCst), 6);
    let _ = std::panic::take_hook();
}

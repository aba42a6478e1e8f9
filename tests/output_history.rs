//! `history.csv`: header, exact round trip of every number, flushing, error cases.

use nmm::output::HistoryWriter;
use std::path::Path;

fn cols(names: &[&str]) -> Vec<String> {
    names.iter().map(|s| s.to_string()).collect()
}

fn read_records(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let mut r = csv::ReaderBuilder::new()
        .has_headers(true)
        .from_path(path)
        .unwrap();
    let header = r.headers().unwrap().iter().map(String::from).collect();
    let rows = r
        .records()
        .map(|rec| rec.unwrap().iter().map(String::from).collect())
        .collect();
    (header, rows)
}

#[test]
fn header_and_rows_round_trip_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("history.csv");
    let columns = cols(&["top.ux", "top.uy", "joint.fn", "odd,name \"q\""]);
    let rows: Vec<(usize, f64, [f64; 4], usize)> = vec![
        (0, 0.0, [0.0, -0.0, 1.0, 2.0], 0),
        (1, 1e-3, [0.1 + 0.2, 1e-300, 5e-324, f64::MAX], 3),
        (
            2,
            2e-3,
            [
                -1.234_567_890_123_456_7e-7,
                1e16,
                9.999_999_999_999_998e15,
                -f64::MIN_POSITIVE,
            ],
            12,
        ),
        (
            1_000_000,
            1234.5678,
            [std::f64::consts::PI, -std::f64::consts::E, 1e-5, 9.99e-6],
            1,
        ),
    ];
    {
        let mut w = HistoryWriter::create(&path, &columns).unwrap();
        for (s, t, v, it) in &rows {
            w.write_row(*s, *t, v, *it).unwrap();
        }
        assert_eq!(w.rows(), rows.len());
        assert_eq!(w.non_finite_count(), 0);
    }
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(
        text.starts_with("step,time,top.ux,top.uy,joint.fn,\"odd,name \"\"q\"\"\",iterations\n")
    );
    let (header, parsed) = read_records(&path);
    assert_eq!(
        header,
        [
            "step",
            "time",
            "top.ux",
            "top.uy",
            "joint.fn",
            "odd,name \"q\"",
            "iterations"
        ]
    );
    assert_eq!(parsed.len(), rows.len());
    for ((s, t, v, it), rec) in rows.iter().zip(&parsed) {
        assert_eq!(rec.len(), 7);
        assert_eq!(rec[0].parse::<usize>().unwrap(), *s);
        assert_eq!(rec[1].parse::<f64>().unwrap().to_bits(), t.to_bits());
        for (k, x) in v.iter().enumerate() {
            let back: f64 = rec[2 + k].parse().unwrap();
            assert_eq!(
                back.to_bits(),
                x.to_bits(),
                "column {k}: {x:e} written as {}",
                rec[2 + k]
            );
        }
        assert_eq!(rec[6].parse::<usize>().unwrap(), *it);
    }
    // Short fields: no padding, no needless digits.
    assert_eq!(parsed[1][2], "0.30000000000000004");
    assert_eq!(parsed[1][3], "1e-300");
    assert_eq!(parsed[0][3], "-0");
}

#[test]
fn rows_reach_the_file_before_the_writer_is_dropped() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("history.csv");
    let mut w = HistoryWriter::create(&path, &cols(&["a"])).unwrap();
    // Header is on disk at once.
    assert_eq!(
        std::fs::read_to_string(&path).unwrap(),
        "step,time,a,iterations\n"
    );
    w.write_row(1, 0.5, &[2.5], 4).unwrap();
    // Default: every row is flushed.
    assert_eq!(
        std::fs::read_to_string(&path).unwrap(),
        "step,time,a,iterations\n1,0.5,2.5,4\n"
    );
}

#[test]
fn buffered_rows_are_flushed_every_n_and_on_drop() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("history.csv");
    let lines = |p: &Path| std::fs::read_to_string(p).unwrap().lines().count();
    let mut w = HistoryWriter::create(&path, &cols(&["a"]))
        .unwrap()
        .with_flush_every(3);
    w.write_row(0, 0.0, &[0.0], 0).unwrap();
    w.write_row(1, 0.1, &[1.0], 1).unwrap();
    assert_eq!(lines(&path), 1, "two rows still buffered");
    w.write_row(2, 0.2, &[2.0], 1).unwrap();
    assert_eq!(lines(&path), 4, "third row triggers the flush");
    w.write_row(3, 0.3, &[3.0], 1).unwrap();
    assert_eq!(lines(&path), 4);
    drop(w);
    assert_eq!(lines(&path), 5, "drop flushes the rest");
}

#[test]
fn non_finite_values_are_written_as_nan_inf_and_counted() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("history.csv");
    let mut w = HistoryWriter::create(&path, &cols(&["a", "b", "c"])).unwrap();
    w.write_row(7, 0.7, &[f64::NAN, f64::INFINITY, f64::NEG_INFINITY], 50)
        .unwrap();
    assert_eq!(w.non_finite_count(), 3);
    drop(w);
    let (_, rows) = read_records(&path);
    assert_eq!(rows[0], ["7", "0.7", "nan", "inf", "-inf", "50"]);
    assert!(rows[0][2].parse::<f64>().unwrap().is_nan());
    assert_eq!(rows[0][3].parse::<f64>().unwrap(), f64::INFINITY);
    assert_eq!(rows[0][4].parse::<f64>().unwrap(), f64::NEG_INFINITY);
}

#[test]
fn bad_rows_and_bad_columns_are_errors() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("history.csv");
    let mut w = HistoryWriter::create(&path, &cols(&["a", "b"])).unwrap();
    let e = w.write_row(0, 0.0, &[1.0], 1).unwrap_err();
    assert_eq!(e.kind(), std::io::ErrorKind::InvalidInput);
    assert_eq!(w.rows(), 0);
    drop(w);
    assert_eq!(
        std::fs::read_to_string(&path).unwrap(),
        "step,time,a,b,iterations\n"
    );

    for bad in [&["time"][..], &["iterations"], &["x", "x"], &["step"]] {
        let e = HistoryWriter::create(&dir.path().join("h2.csv"), &cols(bad))
            .err()
            .unwrap();
        assert_eq!(e.kind(), std::io::ErrorKind::InvalidInput, "{bad:?}");
    }
    let missing_dir = dir.path().join("no/such/dir/history.csv");
    assert!(HistoryWriter::create(&missing_dir, &cols(&["a"])).is_err());
}

#[test]
fn no_monitor_columns_is_valid() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("history.csv");
    let mut w = HistoryWriter::create(&path, &[]).unwrap();
    w.write_row(0, 0.0, &[], 0).unwrap();
    drop(w);
    assert_eq!(
        std::fs::read_to_string(&path).unwrap(),
        "step,time,iterations\n0,0,0\n"
    );
}

#[test]
fn a_text_column_and_counts_come_after_iterations() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("history.csv");
    let counts = ["solves", "cuts"];
    let mut w =
        HistoryWriter::create_with_counts(&path, &cols(&["a"]), Some("stage"), &counts).unwrap();
    w.write_row_counts(1, 0.5, &[2.5], 4, Some("settle"), &[29, 1])
        .unwrap();
    // a row without its counts, or without its text, is refused and nothing written
    for (text, c) in [(Some("settle"), &[4][..]), (None, &[4, 0][..])] {
        let e = w.write_row_counts(2, 1.0, &[2.5], 4, text, c).unwrap_err();
        assert_eq!(e.kind(), std::io::ErrorKind::InvalidInput);
    }
    assert!(w.write_row(2, 1.0, &[2.5], 4).is_err());
    assert_eq!(w.rows(), 1);
    drop(w);
    assert_eq!(
        std::fs::read_to_string(&path).unwrap(),
        "step,time,a,iterations,stage,solves,cuts\n1,0.5,2.5,4,settle,29,1\n"
    );
    // a monitor column may not take a trailing column's name
    for bad in ["solves", "stage"] {
        let e = HistoryWriter::create_with_counts(
            &dir.path().join("h2.csv"),
            &cols(&[bad]),
            Some("stage"),
            &counts,
        )
        .err()
        .unwrap();
        assert_eq!(e.kind(), std::io::ErrorKind::InvalidInput, "{bad}");
    }
}

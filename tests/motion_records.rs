//! Base motion record readers (`nmm::motion::read_record`) on small files with
//! the real header layouts of PEER NGA-West2 `.AT2`, NIED K-NET / KiK-net ASCII
//! and CSV: values, units, time axis, components, every error naming the file
//! and line, and no panic on random or mutated input.

#[path = "support/proptest_cases.rs"]
mod proptest_cases;

use nmm::motion::read_record;
use proptest::prelude::*;
use std::path::{Path, PathBuf};

const G: f64 = 9.80665;

fn write(dir: &Path, name: &str, text: &[u8]) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-12 * (1.0 + a.abs().max(b.abs()))
}

/// Ok records: non-empty, finite, strictly increasing time.
fn assert_valid(s: &[[f64; 3]]) {
    assert!(!s.is_empty());
    assert!(s.iter().all(|r| r.iter().all(|v| v.is_finite())));
    assert!(s.windows(2).all(|w| w[1][0] > w[0][0]));
}

/// An error is one line, names the file and (except for I/O) a line number.
fn assert_error(e: &str, file: &str, line: usize) {
    assert!(!e.contains('\n'), "multi-line error: {e}");
    let want = format!("{file}: line {line}:");
    assert!(e.contains(&want), "expected '{want}' in: {e}");
}

// ---------------------------------------------------------------- PEER ----

const PEER_VALUES: [f64; 12] = [
    0.3468084E-03,
    0.3498234E-03,
    0.3498970E-03,
    0.3436014E-03,
    0.3366009E-03,
    -0.1234567E-02,
    -0.2000000E-02,
    0.1500000E-01,
    0.2612000E-01,
    -0.3010000E-01,
    0.1000000E-03,
    0.0000000E+00,
];

fn peer_text(units: &str, npts_line: &str, values: &[&str]) -> String {
    let mut s = String::new();
    s.push_str("PEER NGA STRONG MOTION DATABASE RECORD\n");
    s.push_str("Imperial Valley-06, 10/15/1979, El Centro Array #6, 230\n");
    s.push_str(&format!("ACCELERATION TIME SERIES IN UNITS OF {units}\n"));
    s.push_str(npts_line);
    s.push('\n');
    for chunk in values.chunks(5) {
        for v in chunk {
            s.push_str(&format!("  {v}"));
        }
        s.push('\n');
    }
    s
}

/// The values as an AT2 writer prints them (`  .3468084E-03`).
fn peer_tokens() -> Vec<String> {
    PEER_VALUES
        .iter()
        .map(|&v| {
            if v == 0.0 {
                return ".0000000E+00".to_string();
            }
            let e = v.abs().log10().floor() as i32 + 1;
            let m = format!("{:.7}", v.abs() / 10f64.powi(e));
            let sign = if v < 0.0 { "-" } else { "" };
            format!("{sign}{}E{e:+03}", m.trim_start_matches('0'))
        })
        .collect()
}

fn peer_default() -> String {
    let toks = peer_tokens();
    let toks: Vec<&str> = toks.iter().map(String::as_str).collect();
    peer_text("G", "NPTS=    12, DT=   .0050 SEC", &toks)
}

#[test]
fn peer_nga_west2_values_in_g() {
    let dir = tempfile::tempdir().unwrap();
    let text = peer_default();
    assert!(text.contains("  .3468084E-03"), "{text}");
    let p = write(dir.path(), "RSN181_IMPVALL.H_H-E06230.AT2", text.as_bytes());
    let s = read_record(&p, None, "x").unwrap();
    assert_eq!(s.len(), 12);
    for (i, r) in s.iter().enumerate() {
        assert!(close(r[0], i as f64 * 0.005), "t[{i}] = {}", r[0]);
        assert!(close(r[1], PEER_VALUES[i] * G), "a[{i}] = {}", r[1]);
        assert_eq!(r[2], 0.0);
    }
    // same file driving the vertical axis
    let s = read_record(&p, Some("peer"), "y").unwrap();
    assert!(close(s[8][2], 0.02612 * G) && s[8][1] == 0.0);
}

#[test]
fn peer_older_layout_and_other_units() {
    let dir = tempfile::tempdir().unwrap();
    let text = "PEER STRONG MOTION DATABASE RECORD. PROCESSING BY PACIFIC ENGINEERING.\n\
                IMPERIAL VALLEY 10/15/79 2316, EL CENTRO ARRAY #6, 230\n\
                ACCELERATION TIME HISTORY IN UNITS OF G\n\
                \x20   7    0.01000    NPTS, DT\n\
                \x20 .1000E+00  -.2000E+00   .3000E+00   .4000E+00   .5000E+00\n\
                \x20 .6000E+00   .7000E+00\n";
    let p = write(dir.path(), "ELC230.at2", text.as_bytes());
    let s = read_record(&p, None, "x").unwrap();
    assert_eq!(s.len(), 7);
    assert!(close(s[6][0], 0.06) && close(s[1][1], -0.2 * G));

    let text = peer_text(
        "CM/S/S",
        "NPTS=     3, DT=   .0100 SEC",
        &["12.5", "-3.0", "0.0"],
    );
    let p = write(dir.path(), "cm.AT2", text.as_bytes());
    let s = read_record(&p, None, "x").unwrap();
    assert!(close(s[0][1], 0.125) && close(s[1][1], -0.03) && close(s[2][0], 0.02));

    let text = peer_text("CM/S^2", "NPTS=     2, DT=   .0100 SEC", &["100.0", "1.0"]);
    let p = write(dir.path(), "cm2.AT2", text.as_bytes());
    assert!(close(read_record(&p, None, "x").unwrap()[0][1], 1.0));

    let text = peer_text("M/S/S", "NPTS=     2, DT=   .0200 SEC", &["1.5", "-2.5"]);
    let p = write(dir.path(), "ms.AT2", text.as_bytes());
    let s = read_record(&p, None, "x").unwrap();
    assert!(close(s[1][1], -2.5) && close(s[1][0], 0.02));
}

#[test]
fn peer_malformed_files_name_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    let good = peer_default();
    let lines: Vec<&str> = good.lines().collect();

    // truncated: last value line missing → 10 of 12 values
    let truncated = lines[..6].join("\n");
    let p = write(dir.path(), "motion.AT2", truncated.as_bytes());
    let e = read_record(&p, None, "x").unwrap_err();
    assert_error(&e, "motion.AT2", 4);
    assert!(e.contains("NPTS=12 but only 10 values"), "{e}");

    // bad number on line 7
    let mut bad = lines.clone();
    bad[6] = "  .1000E+00  abc  .3000E+00";
    let p = write(dir.path(), "motion.AT2", bad.join("\n").as_bytes());
    let e = read_record(&p, None, "x").unwrap_err();
    assert!(
        e.ends_with("motion.AT2: line 7: cannot read number 'abc'"),
        "{e}"
    );

    // NaN value
    let mut bad = lines.clone();
    bad[5] = "  NaN  .1E+00  .1E+00  .1E+00  .1E+00";
    let p = write(dir.path(), "nan.AT2", bad.join("\n").as_bytes());
    assert_error(&read_record(&p, None, "x").unwrap_err(), "nan.AT2", 6);

    // too many values
    let extra = format!("{good}  .1000E+00\n");
    let p = write(dir.path(), "extra.AT2", extra.as_bytes());
    let e = read_record(&p, None, "x").unwrap_err();
    assert_error(&e, "extra.AT2", 8);

    // unknown unit
    let p = write(
        dir.path(),
        "ft.AT2",
        good.replace("UNITS OF G", "UNITS OF FT/S/S").as_bytes(),
    );
    let e = read_record(&p, None, "x").unwrap_err();
    assert_error(&e, "ft.AT2", 3);
    assert!(e.contains("FT/S/S"), "{e}");

    // velocity file read as acceleration
    let p = write(
        dir.path(),
        "vel.AT2",
        good.replace("ACCELERATION", "VELOCITY").as_bytes(),
    );
    assert_error(&read_record(&p, None, "x").unwrap_err(), "vel.AT2", 3);

    // missing header line (the event line): units land on line 2, NPTS on 3
    let mut missing = lines.clone();
    missing.remove(1);
    let p = write(dir.path(), "short.AT2", missing.join("\n").as_bytes());
    assert_error(&read_record(&p, None, "x").unwrap_err(), "short.AT2", 3);

    // garbled NPTS line, zero DT, header only
    let p = write(
        dir.path(),
        "npts.AT2",
        good.replace("NPTS=    12, DT=   .0050 SEC", "NPTS=  twelve, DT= .005")
            .as_bytes(),
    );
    assert_error(&read_record(&p, None, "x").unwrap_err(), "npts.AT2", 4);
    let p = write(
        dir.path(),
        "dt.AT2",
        good.replace("DT=   .0050", "DT=   .0000").as_bytes(),
    );
    assert_error(&read_record(&p, None, "x").unwrap_err(), "dt.AT2", 4);
    let p = write(dir.path(), "head.AT2", lines[..2].join("\n").as_bytes());
    assert_error(&read_record(&p, None, "x").unwrap_err(), "head.AT2", 3);

    // a single-component record needs an axis
    let p = write(dir.path(), "ok.AT2", good.as_bytes());
    let e = read_record(&p, None, "z").unwrap_err();
    assert!(e.contains("ok.AT2") && e.contains("component"), "{e}");
}

// ---------------------------------------------------------------- K-NET ---

const KNET_COUNTS: [i64; 19] = [
    -2119, -2120, -2122, -2118, -2115, -2117, -2121, -2119, -1800, -2500, 150000, -160000, -2119,
    -2119, -2119, -2119, 0, 12, -7,
];

fn knet_header(dir_field: &str, freq: &str, scale: &str) -> Vec<String> {
    [
        "Origin Time       2011/03/11 14:46:00".to_string(),
        "Lat.              38.103".into(),
        "Long.             142.860".into(),
        "Depth. (km)       24".into(),
        "Mag.              9.0".into(),
        "Station Code      MYG004".into(),
        "Station Lat.      38.7292".into(),
        "Station Long.     141.0217".into(),
        "Station Height(m) 230".into(),
        "Record Time       2011/03/11 14:46:29".into(),
        format!("Sampling Freq(Hz) {freq}"),
        "Duration Time(s)  300".into(),
        format!("Dir.              {dir_field}"),
        format!("Scale Factor      {scale}"),
        "Max. Acc. (gal)   2700.214".into(),
        "Last Correction   2011/03/11 14:46:14".into(),
        "Memo.".into(),
    ]
    .to_vec()
}

fn knet_text(header: &[String], counts: &[i64]) -> String {
    let mut s = header.join("\n");
    s.push('\n');
    for chunk in counts.chunks(8) {
        for c in chunk {
            s.push_str(&format!("{c:>8}"));
        }
        s.push('\n');
    }
    s
}

fn knet_default() -> String {
    knet_text(
        &knet_header("N-S", "100Hz", "3920(gal)/6182761"),
        &KNET_COUNTS,
    )
}

#[test]
fn knet_counts_scaled_and_mean_removed() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(dir.path(), "MYG0041103111446.NS", knet_default().as_bytes());
    let s = read_record(&p, None, "x").unwrap();
    assert_eq!(s.len(), KNET_COUNTS.len());
    let scale = 3920.0 / 6182761.0; // gal per count
    let mean = KNET_COUNTS.iter().sum::<i64>() as f64 / KNET_COUNTS.len() as f64;
    for (i, r) in s.iter().enumerate() {
        assert!(close(r[0], i as f64 / 100.0));
        let want = (KNET_COUNTS[i] as f64 - mean) * scale * 0.01;
        assert!(close(r[1], want), "a[{i}] = {} vs {want}", r[1]);
        assert_eq!(r[2], 0.0);
    }
    // zero mean after correction; 150000 counts ≈ 95 gal ≈ 0.95 m/s²
    assert!(s.iter().map(|r| r[1]).sum::<f64>().abs() < 1e-12);
    assert!((s[10][1] - 0.9644).abs() < 0.01, "{}", s[10][1]);
}

#[test]
fn kiknet_surface_channel_at_200_hz() {
    let dir = tempfile::tempdir().unwrap();
    let text = knet_text(
        &knet_header("4", "200Hz", "7845(gal)/8223790"),
        &[10, -10, 30, -30, 0],
    );
    let p = write(dir.path(), "IWTH250307241026.NS2", text.as_bytes());
    let s = read_record(&p, None, "y").unwrap();
    assert_eq!(s.len(), 5);
    assert!(close(s[4][0], 4.0 / 200.0));
    assert!(close(s[2][2], 30.0 * 7845.0 / 8223790.0 * 0.01));
    assert_eq!(s[2][1], 0.0);
    // explicit format, any extension
    let p = write(dir.path(), "record.txt", text.as_bytes());
    assert_eq!(read_record(&p, Some("knet"), "y").unwrap(), s);
}

#[test]
fn knet_malformed_files_name_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    let good = knet_default();
    let header = knet_header("N-S", "100Hz", "3920(gal)/6182761");

    for (name, scale) in [
        ("s1.NS", "3920/6182761"),
        ("s2.NS", "3920(gal)/0"),
        ("s3.NS", "abc(gal)/6182761"),
        ("s4.NS", "3920(gal)/"),
        ("s5.NS", "-3920(gal)/6182761"),
    ] {
        let text = knet_text(&knet_header("N-S", "100Hz", scale), &KNET_COUNTS);
        let p = write(dir.path(), name, text.as_bytes());
        let e = read_record(&p, None, "x").unwrap_err();
        assert_error(&e, name, 14);
        assert!(e.contains("scale factor"), "{e}");
    }

    // missing header line (Station Code): line 6 holds 'Station Lat.'
    let mut h = header.clone();
    h.remove(5);
    let p = write(
        dir.path(),
        "nocode.NS",
        knet_text(&h, &KNET_COUNTS).as_bytes(),
    );
    let e = read_record(&p, None, "x").unwrap_err();
    assert_error(&e, "nocode.NS", 6);
    assert!(e.contains("Station Code"), "{e}");

    // bad count on the second data line (line 19)
    let bad = good.replacen("   -1800", "   -18x0", 1);
    let p = write(dir.path(), "count.NS", bad.as_bytes());
    let e = read_record(&p, None, "x").unwrap_err();
    assert!(
        e.ends_with("count.NS: line 19: cannot read integer count '-18x0'"),
        "{e}"
    );

    // bad sampling frequency, unknown direction, bad max acc
    let p = write(
        dir.path(),
        "freq.NS",
        knet_text(&knet_header("N-S", "fastHz", "3920(gal)/6182761"), &[1, 2]).as_bytes(),
    );
    assert_error(&read_record(&p, None, "x").unwrap_err(), "freq.NS", 11);
    let p = write(
        dir.path(),
        "dir.NS",
        knet_text(&knet_header("Z", "100Hz", "3920(gal)/6182761"), &[1, 2]).as_bytes(),
    );
    assert_error(&read_record(&p, None, "x").unwrap_err(), "dir.NS", 13);

    // truncated inside the header, and a header with no counts
    let p = write(dir.path(), "cut.NS", header[..9].join("\n").as_bytes());
    assert_error(&read_record(&p, None, "x").unwrap_err(), "cut.NS", 10);
    let p = write(dir.path(), "empty.NS", knet_text(&header, &[]).as_bytes());
    let e = read_record(&p, None, "x").unwrap_err();
    assert!(e.contains("empty.NS") && e.contains("empty record"), "{e}");
}

// ---------------------------------------------------------------- CSV -----

#[test]
fn csv_two_and_three_columns() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(
        dir.path(),
        "motion.csv",
        b"t,ax,ay\n0.0,0.0,0.0\n\n0.01, 0.05 ,-0.02\n0.02,0.1,0.0\n",
    );
    let s = read_record(&p, None, "y").unwrap(); // component ignored with 3 columns
    assert_eq!(
        s,
        vec![[0.0, 0.0, 0.0], [0.01, 0.05, -0.02], [0.02, 0.1, 0.0]]
    );

    let p = write(dir.path(), "h.csv", b"0,1.5\r\n0.5,-2\r\n");
    assert_eq!(
        read_record(&p, None, "x").unwrap(),
        vec![[0.0, 1.5, 0.0], [0.5, -2.0, 0.0]]
    );
    assert_eq!(
        read_record(&p, Some("csv"), "y").unwrap(),
        vec![[0.0, 0.0, 1.5], [0.5, 0.0, -2.0]]
    );
}

#[test]
fn csv_errors_and_missing_files() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(dir.path(), "dec.csv", b"t,ax\n0,0\n0.1,1\n0.1,2\n");
    let e = read_record(&p, None, "x").unwrap_err();
    assert_error(&e, "dec.csv", 4);
    assert!(e.contains("increase"), "{e}");

    let p = write(dir.path(), "nan.csv", b"t,ax\n0,0\n0.1,nan\n");
    assert_error(&read_record(&p, None, "x").unwrap_err(), "nan.csv", 3);
    let p = write(dir.path(), "inf.csv", b"0,0\n0.1,inf\n");
    assert_error(&read_record(&p, None, "x").unwrap_err(), "inf.csv", 2);
    let p = write(dir.path(), "cols.csv", b"0,0,0\n0.1,1\n");
    assert_error(&read_record(&p, None, "x").unwrap_err(), "cols.csv", 2);
    let p = write(dir.path(), "empty.csv", b"");
    let e = read_record(&p, None, "x").unwrap_err();
    assert!(e.contains("empty.csv") && e.contains("empty record"), "{e}");
    let p = write(dir.path(), "hdr.csv", b"t,ax,ay\n\n");
    assert!(read_record(&p, None, "x")
        .unwrap_err()
        .contains("empty record"));

    let missing = dir.path().join("nowhere.csv");
    let e = read_record(&missing, None, "x").unwrap_err();
    assert!(e.contains("nowhere.csv") && !e.contains('\n'), "{e}");

    let p = write(dir.path(), "ok.csv", b"0,0\n");
    let e = read_record(&p, Some("seed"), "x").unwrap_err();
    assert!(e.contains("ok.csv") && e.contains("seed"), "{e}");
}

#[test]
fn format_inference() {
    let dir = tempfile::tempdir().unwrap();
    // contents decide K-NET whatever the extension
    let p = write(dir.path(), "a.EW", knet_default().as_bytes());
    assert_eq!(read_record(&p, None, "x").unwrap().len(), KNET_COUNTS.len());
    // PEER text without the .AT2 extension is read as CSV (and fails there)
    let p = write(dir.path(), "a.txt", peer_default().as_bytes());
    assert!(read_record(&p, None, "x").is_err());
    assert_eq!(read_record(&p, Some("peer"), "x").unwrap().len(), 12);
}

// ------------------------------------------------------------ proptest ----

fn check_no_panic(dir: &Path, name: &str, bytes: &[u8]) {
    let p = write(dir, name, bytes);
    for fmt in [None, Some("csv"), Some("peer"), Some("knet")] {
        match read_record(&p, fmt, "x") {
            Ok(s) => assert_valid(&s),
            Err(e) => {
                assert!(!e.contains('\n'), "multi-line error: {e}");
                assert!(e.contains(name), "error without file name: {e}");
            }
        }
    }
}

/// Bytes that matter to the parsers, mixed with arbitrary ones.
fn interesting_byte() -> impl Strategy<Value = u8> {
    prop_oneof![
        3 => prop::sample::select(b"0123456789.-+eEdD ,\n\r\t()/=NPTSHzgalGnaif".to_vec()),
        1 => any::<u8>(),
    ]
}

fn mutate(mut text: Vec<u8>, edits: &[(usize, u8, u8)]) -> Vec<u8> {
    for &(pos, op, byte) in edits {
        let n = text.len();
        let i = if n == 0 { 0 } else { pos % (n + 1) };
        match op % 4 {
            0 if i < n => text[i] = byte,
            1 => text.insert(i, byte),
            2 if i < n => {
                text.remove(i);
            }
            3 => text.truncate(i),
            _ => text.push(byte),
        }
    }
    text
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(proptest_cases::cases(200)))]

    #[test]
    fn random_bytes_never_panic(bytes in prop::collection::vec(interesting_byte(), 0..600)) {
        let dir = tempfile::tempdir().unwrap();
        check_no_panic(dir.path(), "rand.AT2", &bytes);
        let mut knet = b"Origin Time       ".to_vec();
        knet.extend_from_slice(&bytes);
        check_no_panic(dir.path(), "rand.NS", &knet);
    }

    #[test]
    fn mutated_valid_files_never_panic(
        which in 0usize..3,
        edits in prop::collection::vec((any::<usize>(), any::<u8>(), interesting_byte()), 1..6),
    ) {
        let (name, text) = match which {
            0 => ("mut.AT2", peer_default()),
            1 => ("mut.NS", knet_default()),
            _ => ("mut.csv", "t,ax,ay\n0,0,0\n0.01,0.5,-0.2\n0.02,1e-3,4\n".to_string()),
        };
        let dir = tempfile::tempdir().unwrap();
        check_no_panic(dir.path(), name, &mutate(text.into_bytes(), &edits));
    }
}

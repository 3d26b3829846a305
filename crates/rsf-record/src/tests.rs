//! The reader on the lab formats it reads and the broken files it refuses.

use super::*;

/// time, load point, friction of `n` rows in the given layout.
fn rows(n: usize, sep: &str) -> String {
    (0..n).map(|i| format!("{}{sep}{}{sep}{}\n", i as f64 * 0.5, 10.0 + i as f64, 0.6 + 0.001 * i as f64)).collect()
}

fn spec() -> Spec {
    Spec::timed(vec![Column::new("time_s"), Column::new("lp"), Column::friction("mu")])
}

type Rows = Vec<(u64, Vec<f64>)>;

fn read(text: &str, spec: &Spec) -> Result<(Rows, Summary), ReadError> {
    read_bytes(text.as_bytes(), spec)
}

fn read_bytes(bytes: &[u8], spec: &Spec) -> Result<(Rows, Summary), ReadError> {
    let mut out = vec![];
    let s = read_from(bytes, "f.csv", spec, |l, v| {
        out.push((l, v.to_vec()));
        Ok(())
    })?;
    Ok((out, s))
}

fn values(r: &Rows) -> Vec<Vec<f64>> {
    r.iter().map(|(_, v)| v.clone()).collect()
}

#[test]
fn the_lab_formats_read_to_the_same_numbers() {
    let plain = format!("time_s,lp,mu\n{}", rows(12, ","));
    let want = values(&read(&plain, &spec()).unwrap().0);
    assert_eq!(want.len(), 12);
    assert_eq!(want[3], vec![1.5, 13.0, 0.603]);
    let eu = format!("time_s;lp;mu\n{}", rows(12, ";").replace('.', ","));
    let quoted = format!(
        "\"time_s\",\"lp\",\"mu\"\n{}",
        rows(12, ",").lines().map(|l| format!("\"{}\"\n", l.replace(',', "\",\""))).collect::<String>()
    );
    let variants = [
        ("tab", format!("time_s\tlp\tmu\n{}", rows(12, "\t"))),
        ("spaces", format!("  time_s   lp    mu\n{}", rows(12, "    "))),
        ("crlf", format!("time_s,lp,mu\n{}", rows(12, ",")).replace('\n', "\r\n")),
        ("cr only", format!("time_s,lp,mu\n{}", rows(12, ",")).replace('\n', "\r")),
        ("bom", format!("\u{feff}time_s,lp,mu\n{}", rows(12, ","))),
        ("semicolon + decimal comma", eu),
        ("quoted", quoted),
        ("padded", format!("time_s , lp , mu\n{}", rows(12, " , "))),
        ("units row", format!("time_s,lp,mu\ns,um,-\n{}", rows(12, ","))),
        ("preamble and comments", format!("Machine: BRAVA\nOperator: x\n# note\ntime_s,lp,mu\n\n{}", rows(12, ","))),
        ("trailing delimiter", rows(12, ",").lines().fold("time_s,lp,mu\n".to_string(), |a, l| a + l + ",\n")),
        (
            "trailing delimiter in header too",
            rows(12, ",").lines().fold("time_s,lp,mu,\n".to_string(), |a, l| a + l + ",\n"),
        ),
        (
            "leading index",
            rows(12, ",").lines().enumerate().fold("time_s,lp,mu\n".into(), |a, (i, l)| a + &format!("{i},{l}\n")),
        ),
        ("no final newline", format!("time_s,lp,mu\n{}", rows(12, ",").trim_end())),
        ("empty spreadsheet rows", format!("time_s,lp,mu\n{},,\n,,\n", rows(12, ","))),
    ];
    for (what, text) in variants {
        let got = read(&text, &spec()).unwrap_or_else(|e| panic!("{what}: {e}"));
        assert_eq!(values(&got.0), want, "{what}");
        assert!(got.1.warnings.is_empty(), "{what}: {:?}", got.1.warnings);
    }
}

#[test]
fn other_encodings_are_decoded_and_named() {
    // Windows-1252: µ is the one byte 0xB5
    let mut latin = b"Time(s),Displ(\xB5m),Friction\n".to_vec();
    latin.extend_from_slice(rows(12, ",").as_bytes());
    let spec = Spec::timed(vec![Column::new("Time(s)"), Column::new("Displ(µm)"), Column::friction("Friction")]);
    let (r, s) = read_bytes(&latin, &spec).unwrap();
    assert_eq!(r.len(), 12);
    assert_eq!(s.encoding, Some(TextEncoding::Windows1252));
    assert!(s.warnings[0].contains("Windows-1252"), "{:?}", s.warnings);
    // UTF-16, with and without the byte-order mark, both byte orders
    let text = format!("Time(s)\tDispl(µm)\tFriction\r\n{}", rows(12, "\t").replace('\n', "\r\n"));
    let le: Vec<u8> = text.encode_utf16().flat_map(u16::to_le_bytes).collect();
    let be: Vec<u8> = text.encode_utf16().flat_map(u16::to_be_bytes).collect();
    for (what, bytes, enc) in [
        ("LE+BOM", [vec![0xFF, 0xFE], le.clone()].concat(), TextEncoding::Utf16Le),
        ("LE", le, TextEncoding::Utf16Le),
        ("BE+BOM", [vec![0xFE, 0xFF], be.clone()].concat(), TextEncoding::Utf16Be),
        ("BE", be, TextEncoding::Utf16Be),
    ] {
        let (r, s) = read_bytes(&bytes, &spec).unwrap_or_else(|e| panic!("{what}: {e}"));
        assert_eq!(r.len(), 12, "{what}");
        assert_eq!(r[2].1, vec![1.0, 12.0, 0.602], "{what}");
        assert_eq!(s.encoding, Some(enc), "{what}");
    }
}

fn fails(text: &str, spec: &Spec) -> ReadError {
    match read(text, spec) {
        Ok((r, s)) => panic!("accepted {} rows ({:?}) of\n{}", r.len(), s.warnings, &text[..text.len().min(300)]),
        Err(e) => e,
    }
}

#[test]
fn a_cut_last_line_is_dropped_with_a_warning() {
    let full = format!("time_s,lp,mu\n{}", rows(20, ","));
    let want = values(&read(&full, &spec()).unwrap().0);
    // every cut inside the last row: never a changed number
    let last_start = full.trim_end().rfind('\n').unwrap() + 1;
    for cut in last_start + 1..full.len() - 1 {
        let (r, s) = read(&full[..cut], &spec()).unwrap();
        assert_eq!(values(&r), want[..19], "cut at {cut}: {:?}", &full[last_start..cut]);
        assert!(s.warnings.iter().any(|w| w.contains("cut line")), "cut at {cut}: {:?}", s.warnings);
    }
    // a complete last line without its newline is kept
    let (r, s) = read(full.trim_end(), &spec()).unwrap();
    assert_eq!(values(&r), want);
    assert!(s.warnings.is_empty());
}

#[test]
fn ragged_rows_are_refused_with_line_and_counts() {
    // a trailing delimiter on the data rows but not on every one
    let mut text = format!("time_s,lp,mu\n{}", rows(12, ","));
    text = text.replacen("\n0.5,", ",\n0.5,", 1);
    let e = fails(&text, &spec());
    assert_eq!(e.line, Some(3), "{e}");
    assert!(matches!(e.kind, ReadErrorKind::Ragged { expected: 4, found: 3 }), "{e}");
    // an extra field in one row
    let text = format!("time_s,lp,mu\n{}", rows(12, ",")).replacen("\n3,", "\n3,99,", 1);
    let e = fails(&text, &spec());
    assert_eq!(
        (e.line, e.to_string().contains("4 fields where the header and the rows before have 3")),
        (Some(8), true),
        "{e}"
    );
    // a missing field
    let text = format!("time_s,lp,mu\n{}", rows(12, ",")).replacen("\n3,16,", "\n3,", 1);
    assert!(matches!(fails(&text, &spec()).kind, ReadErrorKind::Ragged { expected: 3, found: 2 }));
    // the header has two columns fewer than the rows: no silent shift
    let text = format!("time_s,mu\n{}", rows(12, ","));
    let s = Spec::timed(vec![Column::new("time_s"), Column::friction("mu")]);
    let e = fails(&text, &s);
    assert!(e.to_string().contains("3 fields where the header has 2, and the first, `0.5`, is not a row index"), "{e}");
}

#[test]
fn invalid_values_are_refused_or_dropped_and_counted() {
    for (bad, kind) in [
        ("1e300", "out of range"),
        ("9.9e37", "out of range"),
        ("-999999", "no-reading value"),
        ("NaN", "not finite"),
        ("inf", "not finite"),
        ("12.5", "out of range"),
    ] {
        let text = format!("time_s,lp,mu\n{}", rows(12, ",")).replacen(",0.605\n", &format!(",{bad}\n"), 1);
        let e = fails(&text, &spec());
        assert_eq!((e.line, e.column.as_deref()), (Some(7), Some("mu")), "{bad}: {e}");
        assert!(e.to_string().contains(kind), "{bad}: {e}");
        let (r, s) = read(&text, &Spec { invalid: InvalidRows::Drop, ..spec() }).unwrap();
        assert_eq!((r.len(), s.dropped_invalid), (11, 1), "{bad}");
        assert!(s.warnings[0].contains("lines 7"), "{:?}", s.warnings);
    }
    // NaN time in the first data row is not a units row
    let text = format!("time_s,lp,mu\n{}", rows(12, ",")).replacen("\n0,", "\nNaN,", 1);
    let e = fails(&text, &spec());
    assert_eq!((e.line, e.column.as_deref()), (Some(2), Some("time_s")), "{e}");
    // non-positive normal stress
    let s = Spec::timed(vec![Column::new("time_s"), Column::positive("lp")]);
    let text = format!("time_s,lp,mu\n{}", rows(12, ",")).replacen(",13,", ",-1,", 1);
    assert!(fails(&text, &s).to_string().contains("-1 must be positive"));
}

#[test]
fn broken_files_are_named() {
    let e = read_bytes(&[0u8; 100_000], &spec()).unwrap_err();
    assert!(matches!(e.kind, ReadErrorKind::Binary), "{e}");
    let e = read_bytes(&vec![b'1'; 3 << 20], &spec()).unwrap_err();
    assert!(matches!(e.kind, ReadErrorKind::LineTooLong), "{e}");
    let e = fails("a,b\n1,2\n", &spec());
    assert!(e.to_string().contains("no header line names the column `time_s`") && e.to_string().contains("a,b"), "{e}");
    let e = fails(&format!("time_s,lp\n{}", rows(12, ",")), &spec());
    assert_eq!((e.line, e.column.as_deref()), (Some(1), Some("mu")));
    let e = fails(&format!("time_s,lp,mu\n{}", rows(12, ",")).replacen("0.603", &"7".repeat(10_000), 1), &spec());
    assert!(e.to_string().len() < 200, "{e}");
    let e = fails(&format!("time_s,lp,mu\n{}", rows(12, ",")).replacen("0.603", "abc", 1), &spec());
    assert!(e.to_string().starts_with("f.csv:5: column `mu`: `abc` is not a number"), "{e}");
    let e = fails(&format!("time_s,lp,mu\n{}", rows(5, ",")), &spec());
    assert!(e.to_string().contains("5 data rows; at least 10"), "{e}");
    let e = fails("time_s,lp,mu\nx,y,z\n", &spec());
    assert!(e.to_string().contains("line 2, the first after the header, has `x` in column `time_s`"), "{e}");
    let e = fails(&format!("time_s,lp,mu\n{}", rows(12, ",")).replacen("\n1.5,", "\n1,", 1), &spec());
    assert!(
        e.to_string().contains("time 1 does not increase (previous 1)") || e.to_string().contains("repeats"),
        "{e}"
    );
}

#[test]
fn a_table_reads_every_column() {
    let dir = std::env::temp_dir().join(format!("rsf-record-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join("t.csv");
    std::fs::write(&p, format!("time_s,lp,mu\n{}", rows(3, ","))).unwrap();
    let t = read_table(&p, "time_s").unwrap();
    assert_eq!(t.names, ["time_s", "lp", "mu"]);
    assert_eq!(t.column("lp").unwrap(), [10.0, 11.0, 12.0]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn rows_outside_the_window_are_not_checked_and_tables_keep_nan() {
    // set-up rows before the window hold a zero normal stress and a sentinel
    let mut text = String::from("time_s,lp,sn\n");
    for i in 0..30 {
        let sn = if i < 10 { "0" } else { "10" };
        let lp = if i == 3 { "-999999".to_string() } else { i.to_string() };
        text += &format!("{i},{lp},{sn}\n");
    }
    let spec = Spec {
        window: (Some(10.0), None),
        ..Spec::timed(vec![Column::new("time_s"), Column::new("lp"), Column::positive("sn")])
    };
    let (r, _) = read(&text, &spec).unwrap();
    assert_eq!((r.len(), r[0].1[0]), (20, 10.0));
    // without the window, the zero is refused
    assert!(read(&text, &Spec { window: (None, None), ..spec.clone() }).is_err());
    // a window in s over a column in ms
    let ms = Spec { window: (Some(0.010), Some(0.020)), window_scale: 1e-3, ..spec };
    assert_eq!(read(&text, &ms).unwrap().0.len(), 11);
    // a reference table keeps the NaN its solver wrote after it stopped
    let (r, _) = read("time_s,mu\n0,0.6\n1,NaN\n", &Spec::all("time_s")).unwrap();
    assert!(r[1].1[1].is_nan());
}

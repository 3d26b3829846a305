//! The record reader against lab export formats and bad input.

use super::*;

fn o() -> ReadOptions {
    ReadOptions::default()
}
fn rows(n: usize) -> String {
    (0..n).map(|i| format!("{},{},{}\n", i as f64 * 0.1, i as f64 * 0.3, 0.6)).collect()
}

#[test]
fn reads_csv_with_comments_and_units() {
    let text = format!("# lab run 42\ntime_s,load_point_um,mu\ns,um,-\n{}", rows(20));
    let r = parse_record(&text, "f.csv", &o()).unwrap();
    assert_eq!(r.len(), 20);
    assert_eq!(r.load_point[2], 0.6);
    let mut mm = o();
    mm.disp_unit = DispUnit::Mm;
    mm.time_unit = TimeUnit::Ms;
    let r = parse_record(&text, "f.csv", &mm).unwrap();
    assert!((r.load_point[2] - 600.0).abs() < 1e-9 && (r.time[2] - 2e-4).abs() < 1e-15);
}

#[test]
fn xlook_style_whitespace_with_index_column_and_preamble() {
    let mut text = String::from(
        "number of records = 12\ncol 1 col 2 col 3\nLP_Disp Shr_stress Time mu\nmic MPa sec .\n12 recs 12 recs 12 recs 12 recs\n",
    );
    for i in 0..12 {
        text += &format!("{} {} 5.5 {} 0.69\n", 1000 + i, 4000.0 + i as f64, 2500.0 + i as f64 * 0.02);
    }
    let opts = ReadOptions { time_col: "Time".into(), lp_col: "LP_Disp".into(), ..o() };
    let r = parse_record(&text, "x.txt", &opts).unwrap();
    assert_eq!(r.len(), 12);
    assert_eq!(r.time[1], 2500.02);
    assert_eq!(r.load_point[1], 4001.0);
    assert_eq!(r.mu[0], 0.69);
}

#[test]
fn shear_over_normal_stress() {
    let text: String = "t,x,tau,sn\n".to_string() + &(0..12).map(|i| format!("{i},{i},5.0,10.0\n")).collect::<String>();
    let base = ReadOptions { time_col: "t".into(), lp_col: "x".into(), shear_col: Some("tau".into()), ..o() };
    let r = parse_record(&text, "s.csv", &ReadOptions { normal_col: Some("sn".into()), ..base.clone() }).unwrap();
    assert_eq!(r.mu[3], 0.5);
    let r = parse_record(&text, "s.csv", &ReadOptions { normal_stress: Some(20.0), ..base.clone() }).unwrap();
    assert_eq!(r.mu[3], 0.25);
    let e = parse_record(&text, "s.csv", &base).unwrap_err().to_string();
    assert!(e.contains("--normal-stress"), "{e}");
}

#[test]
fn bad_input_names_file_line_and_column() {
    let cases = [
        (
            format!("time_s,load_point_um,mu\n{}5.0,x,0.6\n", rows(12)),
            "f.csv:14: column `load_point_um`: `x` is not a number",
        ),
        (format!("time_s,load_point_um,mu\n{}5.0,1,NaN\n", rows(12)), "f.csv:14: column `mu`: NaN is not finite"),
        (
            format!("time_s,load_point_um,mu\n{}0.5,1,0.6\n", rows(12)),
            "f.csv:14: column `time_s`: time 0.5 does not increase",
        ),
        (
            format!("time_s,load_point_um,mu\n{}5.0,1\n", rows(12)),
            "f.csv:14: 2 fields where the header and the rows before have 3",
        ),
        (format!("time_s,lp,mu\n{}", rows(12)), "f.csv:1: column `load_point_um`: no such column"),
        ("a,b,c\n1,2,3\n".to_string(), "no header line names the column `time_s`"),
        (format!("time_s,load_point_um,mu\n{}", rows(3)), "3 data rows; at least 10"),
    ];
    for (text, want) in cases {
        let e = parse_record(&text, "f.csv", &o()).unwrap_err().to_string();
        assert!(e.contains(want), "`{e}` lacks `{want}`");
    }
}

/// Excel's CSV (a byte-order mark), European CSV (semicolons, decimal commas), and a logger
/// that writes two rows per clock tick (refused by default, dropped and counted on request).
#[test]
fn lab_exports_bom_semicolons_decimal_commas_duplicate_times() {
    let bom = "\u{feff}time_s,load_point_um,mu\n".to_string() + &rows(12);
    assert_eq!(parse_record(&bom, "f", &o()).unwrap().len(), 12);
    let mut eu = "\u{feff}time_s;load_point_um;mu\n".to_string();
    for i in 0..12 {
        eu += &format!("{},5;{},25;0,6{}\n", i, i, i % 10);
    }
    let r = parse_record(&eu, "f", &o()).unwrap();
    assert_eq!(r.len(), 12);
    assert_eq!((r.time[1], r.load_point[1], r.mu[3]), (1.5, 1.25, 0.63));
    let mut dup = "time_s,load_point_um,mu\n".to_string() + &rows(12);
    dup += &format!("{},99,0.7\n", 11.0 * 0.1);
    let e = parse_record(&dup, "f", &o()).unwrap_err().to_string();
    assert!(e.contains("repeats the previous row") && e.contains("f:14"), "{e}");
    let r = parse_record(&dup, "f", &ReadOptions { duplicate_times: DuplicateTimes::Drop, ..o() }).unwrap();
    assert_eq!((r.len(), r.dropped_duplicate_times), (12, 1));
}

/// Isolated spikes are found; a jump between two samples (a stick-slip drop) is not one.
#[test]
fn finds_isolated_spikes_but_not_jumps() {
    let mut x: Vec<f64> = (0..200).map(|i| 0.6 + 1e-4 * ((i as f64 * 12.9898).sin() * 43758.5453).fract()).collect();
    x[50] += 0.01;
    x[120] -= 0.008;
    for v in x.iter_mut().skip(160) {
        *v -= 0.02;
    }
    assert_eq!(isolated_spikes(&x), vec![50, 120]);
}

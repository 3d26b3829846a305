//! The reader's boundary under random input (proptest):
//!
//! * **round trip**: random records written in random lab formats (delimiter, quotes, line
//!   ends, byte-order mark, UTF-16, Windows-1252 header, preamble, unit row, padding, trailing
//!   delimiter, leading index, final line end or not) read back to exactly the numbers written;
//! * **cut files**: every prefix of a record (a file cut while copied) is refused or read as an
//!   exact prefix of the rows: never a changed number;
//! * **mutations**: random byte edits (delimiters, quotes, line ends, NUL, non-UTF-8, digits)
//!   never panic or hang, and whatever is accepted, written out again, reads back the same.
//!
//! Case counts are proptest's (`PROPTEST_CASES`); docs/fuzzing.md records a longer campaign.

use proptest::prelude::*;
use rsf_record::{Column, Spec, read_from};

#[derive(Clone, Debug)]
struct Format {
    delim: &'static str,
    quote: bool,
    eol: &'static str,
    bom: bool,
    utf16: bool,
    latin1_header: bool,
    preamble: bool,
    units: bool,
    pad: bool,
    trailing: bool,
    index: bool,
    final_eol: bool,
}

const PLAIN: Format = Format {
    delim: ",",
    quote: false,
    eol: "\n",
    bom: false,
    utf16: false,
    latin1_header: false,
    preamble: false,
    units: false,
    pad: false,
    trailing: false,
    index: false,
    final_eol: true,
};

fn format() -> impl Strategy<Value = Format> {
    (
        prop::sample::select(vec![",", "\t", ";", " ", "   "]),
        any::<bool>(),
        prop::sample::select(vec!["\n", "\r\n", "\r"]),
        any::<[bool; 9]>(),
    )
        .prop_map(|(delim, quote, eol, f)| {
            let spaces = delim.starts_with(' ');
            Format {
                delim,
                quote: quote && !spaces,
                eol,
                bom: f[0] && !f[1],
                utf16: f[1],
                latin1_header: f[2] && !f[1] && !f[0],
                preamble: f[3],
                units: f[4],
                pad: f[5] && !spaces,
                trailing: f[6] && !spaces && !f[7],
                index: f[7],
                final_eol: f[8],
            }
        })
}

/// Rows of (time, load point, friction) with fixed decimals per column, as lab software writes.
fn record() -> impl Strategy<Value = (Vec<[f64; 3]>, [usize; 3])> {
    (10usize..40, 0.001f64..10.0, -1e4f64..1e4, 0.0f64..1.5, (1usize..7, 0usize..5, 3usize..8))
        .prop_flat_map(|(n, dt, lp0, mu0, (d0, d1, d2))| {
            (
                prop::collection::vec((0.5f64..1.5, -10.0f64..10.0, -0.01f64..0.01), n),
                Just((dt, lp0, mu0, [d0, d1, d2])),
            )
        })
        .prop_map(|(steps, (dt, lp0, mu0, decimals))| {
            let round = |x: f64, d: usize| format!("{x:.d$}").parse::<f64>().unwrap();
            let mut t = 0.0;
            let mut rows: Vec<[f64; 3]> = vec![];
            for (k, (a, b, c)) in steps.into_iter().enumerate() {
                t += dt * a;
                let mut tr = round(t, decimals[0]);
                // strictly increasing after rounding
                while rows.last().is_some_and(|r| tr <= r[0]) {
                    t += 10f64.powi(-(decimals[0] as i32));
                    tr = round(t, decimals[0]);
                }
                rows.push([tr, round(lp0 + b * k as f64, decimals[1]), round(mu0 + c, decimals[2])]);
            }
            (rows, decimals)
        })
}

fn write(rows: &[[f64; 3]], dec: [usize; 3], f: &Format) -> Vec<u8> {
    let decimal_comma = f.delim == ";";
    let cell = |s: String| {
        let s = if decimal_comma { s.replace('.', ",") } else { s };
        let s = if f.quote { format!("\"{s}\"") } else { s };
        if f.pad { format!(" {s} ") } else { s }
    };
    let line = |cells: Vec<String>| {
        let mut l = cells.join(f.delim);
        if f.trailing {
            l += f.delim;
        }
        l
    };
    let mut lines = vec![];
    if f.preamble {
        lines.push("Machine: biaxial p4309, operator J. Doe".to_string());
        lines.push("# comment line".to_string());
        lines.push(String::new());
    }
    let lp_name = if f.latin1_header { "Displ(µm)" } else { "lp_um" };
    lines.push(line(["time_s", lp_name, "mu"].map(|s| cell(s.into())).to_vec()));
    if f.units {
        lines.push(line(["s", "um", "-"].map(|s| cell(s.into())).to_vec()));
    }
    for (i, r) in rows.iter().enumerate() {
        let mut cells: Vec<String> = (0..3).map(|c| cell(format!("{:.*}", dec[c], r[c]))).collect();
        if f.index {
            cells.insert(0, i.to_string());
        }
        lines.push(line(cells));
    }
    let mut text = lines.join(f.eol);
    if f.final_eol {
        text += f.eol;
    }
    if f.utf16 {
        let mut b = vec![0xFF, 0xFE];
        b.extend(text.encode_utf16().flat_map(u16::to_le_bytes));
        return b;
    }
    let mut b = if f.bom { vec![0xEF, 0xBB, 0xBF] } else { vec![] };
    if f.latin1_header {
        b.extend(text.chars().map(|c| if c == 'µ' { 0xB5 } else { c as u8 }));
    } else {
        b.extend(text.bytes());
    }
    b
}

fn spec(f: &Format) -> Spec {
    let lp = if f.latin1_header { "Displ(µm)" } else { "lp_um" };
    Spec { min_rows: 1, ..Spec::timed(vec![Column::new("time_s"), Column::new(lp), Column::friction("mu")]) }
}

type Rows = Vec<[f64; 3]>;

fn read(bytes: &[u8], spec: &Spec) -> Result<(Rows, Vec<String>), rsf_record::ReadError> {
    let mut out = vec![];
    let s = read_from(bytes, "fuzz.csv", spec, |_, v| {
        out.push([v[0], v[1], v[2]]);
        Ok(())
    })?;
    Ok((out, s.warnings))
}

fn config() -> ProptestConfig {
    // a hang is a failure, not a stuck CI run
    ProptestConfig { timeout: 20_000, ..ProptestConfig::default() }
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn every_lab_format_reads_back_the_numbers_written((rows, dec) in record(), f in format()) {
        let bytes = write(&rows, dec, &f);
        let (got, warnings) = read(&bytes, &spec(&f)).map_err(|e| TestCaseError::fail(format!("{e}\n{f:?}")))?;
        if f.final_eol || got.len() == rows.len() {
            prop_assert_eq!(&got, &rows, "{:?}", f);
        } else {
            // an unterminated last line shorter than the rows before is dropped, and says so
            prop_assert_eq!(&got[..], &rows[..rows.len() - 1]);
            prop_assert!(warnings.iter().any(|w| w.contains("cut line")), "{:?}", warnings);
        }
    }

    #[test]
    fn a_cut_file_never_changes_a_number((rows, dec) in record(), f in format(), cut in 0.0f64..1.0) {
        let f = Format { utf16: false, ..f };
        let bytes = write(&rows, dec, &f);
        let at = ((bytes.len() as f64) * cut) as usize;
        if let Ok((got, _)) = read(&bytes[..at], &spec(&f)) {
            prop_assert!(got.len() <= rows.len());
            prop_assert_eq!(&got[..], &rows[..got.len()], "cut at {} of {}", at, bytes.len());
        }
    }

    #[test]
    fn mutated_files_never_panic_and_what_is_read_reads_again(
        (rows, dec) in record(),
        f in format(),
        edits in prop::collection::vec((0.0f64..1.0, prop::sample::select(vec![
            b',', b';', b'\t', b' ', b'"', b'\n', b'\r', 0u8, 0xB5, 0xFF, b'-', b'e', b'.', b'9', b'#', b'x',
        ]), 0u8..3), 1..6),
    ) {
        let mut bytes = write(&rows, dec, &f);
        for (at, byte, op) in edits {
            let i = ((bytes.len() as f64) * at) as usize;
            match op {
                0 => bytes.insert(i.min(bytes.len()), byte),
                1 if i < bytes.len() => { bytes.remove(i); }
                _ if i < bytes.len() => bytes[i] = byte,
                _ => {}
            }
        }
        if let Ok((got, _)) = read(&bytes, &spec(&f)) {
            // written again in the plain format, the accepted rows read back bit for bit
            let text: String = std::iter::once("time_s,lp_um,mu\n".to_string())
                .chain(got.iter().map(|r| format!("{},{},{}\n", r[0], r[1], r[2]))).collect();
            let (again, _) = read(text.as_bytes(), &spec(&PLAIN)).map_err(|e| TestCaseError::fail(e.to_string()))?;
            prop_assert_eq!(again, got);
        }
    }
}

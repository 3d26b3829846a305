//! A small CSV writer for figure data in long format: a few label columns, then numbers to 9
//! significant digits in shortest form. Builds a string; no file I/O.

/// A CSV table under construction.
#[derive(Clone, Debug)]
pub struct Csv {
    text: String,
    columns: usize,
}

impl Csv {
    /// A table with this header.
    pub fn new(header: &[&str]) -> Self {
        let mut c = Self { text: String::new(), columns: header.len() };
        let cells: Vec<String> = header.iter().map(|h| quote(h)).collect();
        c.text.push_str(&cells.join(","));
        c.text.push('\n');
        c
    }

    /// One row: `labels` (quoted where needed) then `values`.
    ///
    /// # Panics
    /// If the row does not have as many cells as the header (a programming error).
    pub fn row(&mut self, labels: &[&str], values: &[f64]) {
        assert_eq!(labels.len() + values.len(), self.columns, "CSV row width differs from the header");
        let cells: Vec<String> = labels.iter().map(|l| quote(l)).chain(values.iter().map(|&v| number(v))).collect();
        self.text.push_str(&cells.join(","));
        self.text.push('\n');
    }

    /// One row per point of a curve: `labels`, then `x_i`, `y_i`.
    pub fn curve(&mut self, labels: &[&str], x: &[f64], y: &[f64]) {
        for (a, b) in x.iter().zip(y) {
            self.row(labels, &[*a, *b]);
        }
    }

    /// The CSV text.
    pub fn finish(self) -> String {
        self.text
    }
}

/// `v` rounded to 9 significant digits (far below any plotted difference) in its shortest form;
/// exponent notation for magnitudes below 1e-4 or from 1e15.
fn number(v: f64) -> String {
    let r: f64 = format!("{v:.8e}").parse().expect("a formatted f64 parses");
    if r != 0.0 && !(1e-4..1e15).contains(&r.abs()) { format!("{r:e}") } else { r.to_string() }
}

/// A cell quoted (RFC 4180) when it holds a comma, quote or line break.
fn quote(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) { format!("\"{}\"", s.replace('"', "\"\"")) } else { s.to_string() }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_and_quoting() {
        let mut c = Csv::new(&["law", "x", "y"]);
        c.curve(&["slip, a=1"], &[0.5, 1.0], &[1e-20, -2.0 / 3.0]);
        assert_eq!(c.finish(), "law,x,y\n\"slip, a=1\",0.5,1e-20\n\"slip, a=1\",1,-0.666666667\n");
    }
}

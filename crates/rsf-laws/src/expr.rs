//! Arithmetic expressions of a text-file law: parsed once, evaluated over any [`Real`] — `f64`
//! for the explicit integrators, dual numbers for the exact derivatives that implicit solvers,
//! fits and the conformance kit need.
//!
//! Grammar (precedence low to high): `+ -`, `* /`, unary `-`, `^` (right-associative), then a
//! number, a name, `( … )` or a function call `f(x)` with `f` one of [`Func`]. Names are
//! resolved to slots when the text is parsed, so a misspelt name is an error at load time that
//! names its column, not a NaN at run time.
//!
//! Why rsf owns this parser (about 250 lines) rather than using a crate: evaluation must be
//! generic over the scalar, so that the same tree gives values and exact derivatives. Of the
//! expression crates on crates.io, evalexpr exposes its tree but is AGPL-3.0 since version 12
//! (rsf is MIT); exmex fixes the value type when it parses and differentiates symbolically;
//! meval and fasteval have had no release since 2017 and 2020.

use rsf_core::Real;

/// A function a law's expression may call.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Func {
    /// Natural logarithm.
    Ln,
    /// Base-10 logarithm.
    Log10,
    /// e^x.
    Exp,
    /// Square root.
    Sqrt,
    /// Hyperbolic tangent.
    Tanh,
}

rsf_core::vocabulary!(Func, "function", {
    Ln => "ln",
    Log10 => "log10",
    Exp => "exp",
    Sqrt => "sqrt",
    Tanh => "tanh",
});

/// A parsed expression: a tree over numbers and slots (indices into the values the caller
/// passes to [`Expr::eval`]).
#[derive(Clone, Debug, PartialEq)]
pub enum Expr {
    /// A number.
    Num(f64),
    /// The value in slot `i`.
    Slot(usize),
    /// −x.
    Neg(Box<Expr>),
    /// x + y.
    Add(Box<Expr>, Box<Expr>),
    /// x − y.
    Sub(Box<Expr>, Box<Expr>),
    /// x · y.
    Mul(Box<Expr>, Box<Expr>),
    /// x / y.
    Div(Box<Expr>, Box<Expr>),
    /// x^y.
    Pow(Box<Expr>, Box<Expr>),
    /// f(x).
    Call(Func, Box<Expr>),
}

/// A parse error: what is wrong and the 1-based column (in characters) where it is.
#[derive(Clone, Debug, PartialEq)]
pub struct ParseError {
    /// 1-based column of the offending character.
    pub column: usize,
    /// What is wrong.
    pub message: String,
}

impl std::fmt::Display for ParseError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "column {}: {}", self.column, self.message)
    }
}

impl Expr {
    /// Parses `text`, resolving each name to its index in `names`.
    pub fn parse(text: &str, names: &[&str]) -> Result<Expr, ParseError> {
        let tokens = tokenize(text)?;
        let mut p = Parser { tokens, pos: 0, names, end: text.chars().count() + 1 };
        let e = p.sum()?;
        match p.peek() {
            None => Ok(e),
            Some((col, t)) => Err(ParseError { column: col, message: format!("unexpected {}", t.describe()) }),
        }
    }

    /// The value at `slots` (one value per name given to [`Expr::parse`]).
    pub fn eval<R: Real>(&self, slots: &[R]) -> R {
        match self {
            Expr::Num(x) => R::from(*x),
            Expr::Slot(i) => slots[*i],
            Expr::Neg(x) => -x.eval(slots),
            Expr::Add(x, y) => x.eval(slots) + y.eval(slots),
            Expr::Sub(x, y) => x.eval(slots) - y.eval(slots),
            Expr::Mul(x, y) => x.eval(slots) * y.eval(slots),
            Expr::Div(x, y) => x.eval(slots) / y.eval(slots),
            Expr::Pow(x, y) => {
                let base = x.eval(slots);
                match y.as_ref() {
                    // an integer power keeps a negative base meaningful
                    Expr::Num(n) if n.fract() == 0.0 && n.abs() < 64.0 => base.powi(*n as i32),
                    Expr::Num(n) => base.powf(*n),
                    y => base.powd(y.eval(slots)),
                }
            }
            Expr::Call(f, x) => {
                let x = x.eval(slots);
                match f {
                    Func::Ln => x.ln(),
                    Func::Log10 => x.log10(),
                    Func::Exp => x.exp(),
                    Func::Sqrt => x.sqrt(),
                    Func::Tanh => x.tanh(),
                }
            }
        }
    }

    /// Whether the expression reads slot `i`.
    pub fn reads(&self, i: usize) -> bool {
        match self {
            Expr::Num(_) => false,
            Expr::Slot(j) => *j == i,
            Expr::Neg(x) | Expr::Call(_, x) => x.reads(i),
            Expr::Add(x, y) | Expr::Sub(x, y) | Expr::Mul(x, y) | Expr::Div(x, y) | Expr::Pow(x, y) => {
                x.reads(i) || y.reads(i)
            }
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
enum Token {
    Num(f64),
    Name(String),
    Op(char),
    Open,
    Close,
}

impl Token {
    fn describe(&self) -> String {
        match self {
            Token::Num(x) => format!("number {x}"),
            Token::Name(n) => format!("name `{n}`"),
            Token::Op(c) => format!("`{c}`"),
            Token::Open => "`(`".into(),
            Token::Close => "`)`".into(),
        }
    }
}

fn tokenize(text: &str) -> Result<Vec<(usize, Token)>, ParseError> {
    let chars: Vec<char> = text.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let col = i + 1;
        if c.is_whitespace() {
            i += 1;
        } else if c.is_ascii_digit() || c == '.' {
            let start = i;
            while i < chars.len() && (chars[i].is_ascii_digit() || chars[i] == '.') {
                i += 1;
            }
            // exponent: 1e-3, 2.5E+4
            if i < chars.len() && (chars[i] == 'e' || chars[i] == 'E') {
                let mut j = i + 1;
                if j < chars.len() && (chars[j] == '+' || chars[j] == '-') {
                    j += 1;
                }
                if j < chars.len() && chars[j].is_ascii_digit() {
                    i = j;
                    while i < chars.len() && chars[i].is_ascii_digit() {
                        i += 1;
                    }
                }
            }
            let s: String = chars[start..i].iter().collect();
            let x: f64 =
                s.parse().map_err(|_| ParseError { column: col, message: format!("`{s}` is not a number") })?;
            out.push((col, Token::Num(x)));
        } else if c.is_ascii_alphabetic() || c == '_' {
            let start = i;
            while i < chars.len() && (chars[i].is_ascii_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            out.push((col, Token::Name(chars[start..i].iter().collect())));
        } else {
            let t = match c {
                '+' | '-' | '*' | '/' | '^' => Token::Op(c),
                '(' => Token::Open,
                ')' => Token::Close,
                _ => return Err(ParseError { column: col, message: format!("unexpected character `{c}`") }),
            };
            out.push((col, t));
            i += 1;
        }
    }
    Ok(out)
}

struct Parser<'a> {
    tokens: Vec<(usize, Token)>,
    pos: usize,
    names: &'a [&'a str],
    end: usize,
}

impl Parser<'_> {
    fn peek(&self) -> Option<(usize, &Token)> {
        self.tokens.get(self.pos).map(|(c, t)| (*c, t))
    }
    fn next(&mut self) -> Result<(usize, Token), ParseError> {
        let t = self
            .tokens
            .get(self.pos)
            .cloned()
            .ok_or_else(|| ParseError { column: self.end, message: "the expression ends too soon".into() })?;
        self.pos += 1;
        Ok(t)
    }
    fn eat_op(&mut self, ops: &[char]) -> Option<char> {
        match self.peek() {
            Some((_, Token::Op(c))) if ops.contains(c) => {
                let c = *c;
                self.pos += 1;
                Some(c)
            }
            _ => None,
        }
    }
    fn sum(&mut self) -> Result<Expr, ParseError> {
        let mut e = self.product()?;
        while let Some(op) = self.eat_op(&['+', '-']) {
            let r = self.product()?;
            e = if op == '+' { Expr::Add(e.into(), r.into()) } else { Expr::Sub(e.into(), r.into()) };
        }
        Ok(e)
    }
    fn product(&mut self) -> Result<Expr, ParseError> {
        let mut e = self.unary()?;
        while let Some(op) = self.eat_op(&['*', '/']) {
            let r = self.unary()?;
            e = if op == '*' { Expr::Mul(e.into(), r.into()) } else { Expr::Div(e.into(), r.into()) };
        }
        Ok(e)
    }
    /// Unary minus binds looser than `^`: `-x^2` is `-(x^2)`.
    fn unary(&mut self) -> Result<Expr, ParseError> {
        if self.eat_op(&['-']).is_some() {
            // a negative number is a number (so that `x^-2` is an integer power)
            return Ok(match self.unary()? {
                Expr::Num(x) => Expr::Num(-x),
                e => Expr::Neg(e.into()),
            });
        }
        if self.eat_op(&['+']).is_some() {
            return self.unary();
        }
        self.power()
    }
    fn power(&mut self) -> Result<Expr, ParseError> {
        let base = self.atom()?;
        if self.eat_op(&['^']).is_some() {
            // right-associative; the exponent may carry its own sign: x^-2
            let exp = self.unary()?;
            return Ok(Expr::Pow(base.into(), exp.into()));
        }
        Ok(base)
    }
    fn atom(&mut self) -> Result<Expr, ParseError> {
        let (col, t) = self.next()?;
        match t {
            Token::Num(x) => Ok(Expr::Num(x)),
            Token::Open => {
                let e = self.sum()?;
                self.close(col)?;
                Ok(e)
            }
            Token::Name(n) => {
                if let Some((_, Token::Open)) = self.peek() {
                    let f: Func = n.parse().map_err(|m: String| ParseError { column: col, message: m })?;
                    self.pos += 1;
                    let arg = self.sum()?;
                    self.close(col)?;
                    return Ok(Expr::Call(f, arg.into()));
                }
                match self.names.iter().position(|x| *x == n) {
                    Some(i) => Ok(Expr::Slot(i)),
                    None => Err(ParseError {
                        column: col,
                        message: format!("unknown name `{n}` (known: {})", self.names.join(", ")),
                    }),
                }
            }
            t @ (Token::Op(_) | Token::Close) => Err(ParseError {
                column: col,
                message: format!("expected a number, a name or `(`, found {}", t.describe()),
            }),
        }
    }
    fn close(&mut self, open_col: usize) -> Result<(), ParseError> {
        match self.next() {
            Ok((_, Token::Close)) => Ok(()),
            Ok((col, t)) => Err(ParseError { column: col, message: format!("expected `)`, found {}", t.describe()) }),
            Err(_) => Err(ParseError { column: open_col, message: "this `(` is never closed".into() }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use num_dual::Dual64;

    fn ev(text: &str, vals: &[f64]) -> f64 {
        Expr::parse(text, &["x", "y", "n"]).unwrap().eval(vals)
    }

    #[test]
    fn precedence_and_associativity() {
        let v = [2.0, 3.0, 1.5];
        assert_eq!(ev("1 + x * y", &v), 7.0);
        assert_eq!(ev("(1 + x) * y", &v), 9.0);
        assert_eq!(ev("x ^ y ^ 2", &v), 2f64.powf(9.0));
        assert_eq!(ev("-x ^ 2", &v), -4.0);
        assert_eq!(ev("x ^ -1", &v), 0.5);
        assert_eq!(ev("x - y - 1", &v), -2.0);
        assert_eq!(ev("x / y / 2", &v), 2.0 / 3.0 / 2.0);
        assert_eq!(ev("2.5e-1 * 4E+1", &v), 10.0);
        assert!((ev("ln(exp(x)) + sqrt(y*y) - log10(100) + tanh(0)", &v) - 3.0).abs() < 1e-15);
        assert_eq!(ev("(-x)^2", &v), 4.0);
        assert!((ev("x^n", &v) - 2f64.powf(1.5)).abs() < 1e-15);
        // a negative integer exponent is an integer power: defined, with its derivative, for x < 0
        assert_eq!(Expr::parse("x^-2", &["x"]).unwrap(), Expr::Pow(Expr::Slot(0).into(), Expr::Num(-2.0).into()));
        let d = Expr::parse("x^-2", &["x"]).unwrap().eval(&[Dual64::from_re(-2.0).derivative()]);
        assert!((d.re - 0.25).abs() < 1e-15 && (d.eps - 0.25).abs() < 1e-15, "{d:?}");
    }

    #[test]
    fn errors_name_the_column() {
        let e = Expr::parse("1 - (v*q)^n", &["v", "n"]).unwrap_err();
        assert_eq!(e.column, 8);
        assert!(e.message.contains("unknown name `q`"), "{e}");
        assert_eq!(Expr::parse("1 - (x", &["x"]).unwrap_err().column, 5);
        assert_eq!(Expr::parse("1 + ", &["x"]).unwrap_err().column, 5);
        assert_eq!(Expr::parse("1 $ 2", &["x"]).unwrap_err().column, 3);
        assert!(Expr::parse("sin(x)", &["x"]).unwrap_err().message.contains("unknown function"));
        assert_eq!(Expr::parse("x y", &["x", "y"]).unwrap_err().column, 3);
        assert!(Expr::parse("1.2.3", &[]).is_err());
    }

    /// The dual-number derivative of a parsed expression equals the hand-derived one,
    /// including a power whose exponent is itself a variable.
    #[test]
    fn derivatives_are_exact() {
        let e = Expr::parse("1 - (x*y)^n + ln(x)", &["x", "y", "n"]).unwrap();
        let (x, y, n) = (1.7, 0.4, 1.3);
        let d = e.eval(&[Dual64::from_re(x).derivative(), Dual64::from_re(y), Dual64::from_re(n)]);
        let exact = -n * (x * y).powf(n - 1.0) * y + 1.0 / x;
        assert!((d.eps - exact).abs() < 1e-14, "{} vs {exact}", d.eps);
        let dn = e.eval(&[Dual64::from_re(x), Dual64::from_re(y), Dual64::from_re(n).derivative()]);
        let exact_n = -(x * y).powf(n) * (x * y).ln();
        assert!((dn.eps - exact_n).abs() < 1e-14);
        assert!(e.reads(2) && !Expr::parse("x", &["x", "y"]).unwrap().reads(1));
    }
}

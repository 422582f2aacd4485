//! Expressions in text: a recursive-descent parser of the grammar
//!
//! ```text
//! sum     = product { ("+" | "-") product }
//! product = unary { ("*" | "/") unary }
//! unary   = ("-" | "+") unary | power
//! power   = primary [ "^" unary ]            (right-associative: a^b^c = a^(b^c))
//! primary = number | name | name "(" sum { "," sum } ")" | "(" sum ")"
//! ```
//!
//! so that unary minus binds more loosely than `^` (`-q^2 = -(q²)`, as in mathematics) and more
//! tightly than `*` and `/`. Numbers are decimal with an optional exponent (`1e-3`, `2.5E+4`);
//! names are letters, digits and `_`, beginning with a letter or `_`. The input is bounded
//! ([`MAX_LENGTH`] bytes, [`MAX_DEPTH`] levels of nesting, both checked before recursing), so no
//! input can exhaust the stack.
//!
//! Reference: N. Wirth, *Compiler Construction*, Addison-Wesley 1996, ch. 4 (recursive descent).

use crate::error::{Error, Result};
use num_dual::DualNum;

/// The longest expression accepted, in bytes.
pub const MAX_LENGTH: usize = 10_000;

/// The deepest nesting accepted: parentheses, function calls, signs and exponents each add one
/// level.
pub const MAX_DEPTH: usize = 64;

/// The greatest height of the expression tree accepted (a sum of `k` terms is `k − 1` levels
/// high), so that every walk of the tree stays within a small stack.
pub const MAX_HEIGHT: usize = 512;

/// A function an expression may call.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Func {
    /// `sin x`.
    Sin,
    /// `cos x`.
    Cos,
    /// `tan x`.
    Tan,
    /// `exp x`.
    Exp,
    /// `ln x` (also written `log x`).
    Ln,
    /// `√x`.
    Sqrt,
    /// `sinh x`.
    Sinh,
    /// `cosh x`.
    Cosh,
    /// `tanh x`.
    Tanh,
    /// `asin x`.
    Asin,
    /// `acos x`.
    Acos,
    /// `atan x`.
    Atan,
    /// `atan2(y, x)`.
    Atan2,
    /// `pow(x, y) = x^y`.
    Pow,
}

/// The functions by name, with their number of arguments.
pub const FUNCTIONS: [(&str, Func, usize); 15] = [
    ("sin", Func::Sin, 1),
    ("cos", Func::Cos, 1),
    ("tan", Func::Tan, 1),
    ("exp", Func::Exp, 1),
    ("ln", Func::Ln, 1),
    ("log", Func::Ln, 1),
    ("sqrt", Func::Sqrt, 1),
    ("sinh", Func::Sinh, 1),
    ("cosh", Func::Cosh, 1),
    ("tanh", Func::Tanh, 1),
    ("asin", Func::Asin, 1),
    ("acos", Func::Acos, 1),
    ("atan", Func::Atan, 1),
    ("atan2", Func::Atan2, 2),
    ("pow", Func::Pow, 2),
];

/// The named constants.
pub const CONSTANTS: [(&str, f64); 1] = [("pi", std::f64::consts::PI)];

/// A binary operation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BinOp {
    /// `a + b`.
    Add,
    /// `a − b`.
    Sub,
    /// `a · b`.
    Mul,
    /// `a / b`.
    Div,
    /// `a^b`.
    Pow,
}

/// A parsed expression; variables are indices into the names it was parsed with.
#[derive(Clone, Debug, PartialEq)]
pub enum Expr {
    /// A number (or a named constant).
    Num(f64),
    /// The variable of this index.
    Var(usize),
    /// `−a`.
    Neg(Box<Expr>),
    /// `a ∘ b`.
    Bin(BinOp, Box<Expr>, Box<Expr>),
    /// A function of its arguments.
    Call(Func, Vec<Expr>),
}

impl Expr {
    /// The value when the expression depends on no variable.
    pub fn constant(&self) -> Option<f64> {
        match self {
            Expr::Num(c) => Some(*c),
            Expr::Var(_) => None,
            Expr::Neg(a) => a.constant().map(|a| -a),
            Expr::Bin(op, a, b) => {
                let (a, b) = (a.constant()?, b.constant()?);
                Some(binary(*op, a, b))
            }
            Expr::Call(f, args) => {
                let v: Option<Vec<f64>> = args.iter().map(Expr::constant).collect();
                Some(call(*f, &v?))
            }
        }
    }

    /// Whether variable `i` occurs.
    pub fn uses(&self, i: usize) -> bool {
        match self {
            Expr::Num(_) => false,
            Expr::Var(j) => *j == i,
            Expr::Neg(a) => a.uses(i),
            Expr::Bin(_, a, b) => a.uses(i) || b.uses(i),
            Expr::Call(_, args) => args.iter().any(|a| a.uses(i)),
        }
    }

    /// The value at `vars` (indexed as the names), on any number type. A power `a^b` with a
    /// constant exponent is `powi`/`powf` of it; otherwise `exp(b ln a)`.
    ///
    /// # Panics
    /// If a variable index is out of range of `vars` (never for an expression parsed with as
    /// many names as `vars` holds).
    pub fn eval<D: DualNum<f64> + Copy>(&self, vars: &[D]) -> D {
        match self {
            Expr::Num(c) => D::from(*c),
            Expr::Var(i) => vars[*i],
            Expr::Neg(a) => -a.eval(vars),
            Expr::Bin(BinOp::Pow, a, b) => power(a.eval(vars), b, vars),
            Expr::Bin(op, a, b) => {
                let (a, b) = (a.eval(vars), b.eval(vars));
                match op {
                    BinOp::Add => a + b,
                    BinOp::Sub => a - b,
                    BinOp::Mul => a * b,
                    _ => a / b,
                }
            }
            Expr::Call(Func::Pow, args) => power(args[0].eval(vars), &args[1], vars),
            Expr::Call(f, args) => {
                let a = args[0].eval(vars);
                match f {
                    Func::Sin => a.sin(),
                    Func::Cos => a.cos(),
                    Func::Tan => a.tan(),
                    Func::Exp => a.exp(),
                    Func::Ln => a.ln(),
                    Func::Sqrt => a.sqrt(),
                    Func::Sinh => a.sinh(),
                    Func::Cosh => a.cosh(),
                    Func::Tanh => a.tanh(),
                    Func::Asin => a.asin(),
                    Func::Acos => a.acos(),
                    Func::Atan => a.atan(),
                    _ => a.atan2(args[1].eval(vars)),
                }
            }
        }
    }
}

fn power<D: DualNum<f64> + Copy>(a: D, b: &Expr, vars: &[D]) -> D {
    match b.constant() {
        Some(c) if c.fract() == 0.0 && c.abs() <= 64.0 => a.powi(c as i32),
        Some(c) => a.powf(c),
        None => (b.eval(vars) * a.ln()).exp(),
    }
}

fn binary(op: BinOp, a: f64, b: f64) -> f64 {
    match op {
        BinOp::Add => a + b,
        BinOp::Sub => a - b,
        BinOp::Mul => a * b,
        BinOp::Div => a / b,
        BinOp::Pow => power::<f64>(a, &Expr::Num(b), &[]),
    }
}

fn call(f: Func, a: &[f64]) -> f64 {
    let args: Vec<Expr> = a.iter().map(|&x| Expr::Num(x)).collect();
    Expr::Call(f, args).eval::<f64>(&[])
}

/// The error at 1-based character column `column` of `text`.
fn error(text: &str, column: usize, reason: impl Into<String>) -> Error {
    Error::Parse {
        expression: text.to_string(),
        column,
        reason: reason.into(),
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Tok<'a> {
    Num(f64),
    Name(&'a str),
    Sym(char),
    End,
}

/// Tokens with their 1-based character columns.
fn lex(text: &str) -> Result<Vec<(Tok<'_>, usize)>> {
    let mut out = Vec::new();
    let chars: Vec<(usize, char)> = text.char_indices().collect();
    let mut i = 0;
    while i < chars.len() {
        let (at, c) = chars[i];
        let column = i + 1;
        if c.is_whitespace() {
            i += 1;
        } else if c.is_ascii_digit()
            || (c == '.' && chars.get(i + 1).is_some_and(|d| d.1.is_ascii_digit()))
        {
            let mut j = i;
            while j < chars.len() && (chars[j].1.is_ascii_digit() || chars[j].1 == '.') {
                j += 1;
            }
            if j < chars.len() && (chars[j].1 == 'e' || chars[j].1 == 'E') {
                let mut k = j + 1;
                if k < chars.len() && (chars[k].1 == '+' || chars[k].1 == '-') {
                    k += 1;
                }
                if k < chars.len() && chars[k].1.is_ascii_digit() {
                    while k < chars.len() && chars[k].1.is_ascii_digit() {
                        k += 1;
                    }
                    j = k;
                }
            }
            let end = chars.get(j).map_or(text.len(), |c| c.0);
            let s = &text[at..end];
            let v: f64 = s
                .parse()
                .map_err(|_| error(text, column, format!("malformed number `{s}`")))?;
            if !v.is_finite() {
                return Err(error(text, column, format!("number `{s}` overflows")));
            }
            out.push((Tok::Num(v), column));
            i = j;
        } else if c.is_alphabetic() || c == '_' {
            let mut j = i;
            while j < chars.len() && (chars[j].1.is_alphanumeric() || chars[j].1 == '_') {
                j += 1;
            }
            let end = chars.get(j).map_or(text.len(), |c| c.0);
            out.push((Tok::Name(&text[at..end]), column));
            i = j;
        } else if "+-*/^(),".contains(c) {
            out.push((Tok::Sym(c), column));
            i += 1;
        } else if c == '−' {
            out.push((Tok::Sym('-'), column));
            i += 1;
        } else {
            return Err(error(text, column, format!("unexpected character `{c}`")));
        }
    }
    out.push((Tok::End, chars.len() + 1));
    Ok(out)
}

struct Parser<'a, 'n> {
    text: &'a str,
    toks: Vec<(Tok<'a>, usize)>,
    at: usize,
    names: &'n [&'n str],
}

impl<'a> Parser<'a, '_> {
    fn peek(&self) -> Tok<'a> {
        self.toks[self.at].0
    }

    fn column(&self) -> usize {
        self.toks[self.at].1
    }

    fn fail<T>(&self, reason: impl Into<String>) -> Result<T> {
        Err(error(self.text, self.column(), reason))
    }

    fn found(&self) -> String {
        match self.peek() {
            Tok::Num(v) => format!("the number {v}"),
            Tok::Name(n) => format!("`{n}`"),
            Tok::Sym(c) => format!("`{c}`"),
            Tok::End => "the end".into(),
        }
    }

    fn deeper(&self, depth: usize) -> Result<usize> {
        if depth >= MAX_DEPTH {
            return self.fail(format!("nested more than {MAX_DEPTH} levels deep"));
        }
        Ok(depth + 1)
    }

    /// The height of a new node over children of heights `a` and `b`, refused beyond
    /// [`MAX_HEIGHT`].
    fn taller(&self, a: usize, b: usize) -> Result<usize> {
        let h = a.max(b) + 1;
        if h > MAX_HEIGHT {
            return self.fail(format!(
                "the expression is more than {MAX_HEIGHT} operations high (split it into \
                 parenthesised groups)"
            ));
        }
        Ok(h)
    }

    fn sum(&mut self, depth: usize) -> Result<(Expr, usize)> {
        let (mut a, mut ha) = self.product(depth)?;
        while let Tok::Sym(c @ ('+' | '-')) = self.peek() {
            self.at += 1;
            let (b, hb) = self.product(depth)?;
            ha = self.taller(ha, hb)?;
            let op = if c == '+' { BinOp::Add } else { BinOp::Sub };
            a = Expr::Bin(op, Box::new(a), Box::new(b));
        }
        Ok((a, ha))
    }

    fn product(&mut self, depth: usize) -> Result<(Expr, usize)> {
        let (mut a, mut ha) = self.unary(depth)?;
        while let Tok::Sym(c @ ('*' | '/')) = self.peek() {
            self.at += 1;
            let (b, hb) = self.unary(depth)?;
            ha = self.taller(ha, hb)?;
            let op = if c == '*' { BinOp::Mul } else { BinOp::Div };
            a = Expr::Bin(op, Box::new(a), Box::new(b));
        }
        Ok((a, ha))
    }

    fn unary(&mut self, depth: usize) -> Result<(Expr, usize)> {
        match self.peek() {
            Tok::Sym('-') => {
                let depth = self.deeper(depth)?;
                self.at += 1;
                let (a, h) = self.unary(depth)?;
                Ok((Expr::Neg(Box::new(a)), self.taller(h, 0)?))
            }
            Tok::Sym('+') => {
                let depth = self.deeper(depth)?;
                self.at += 1;
                self.unary(depth)
            }
            _ => self.power(depth),
        }
    }

    fn power(&mut self, depth: usize) -> Result<(Expr, usize)> {
        let (a, ha) = self.primary(depth)?;
        if self.peek() == Tok::Sym('^') {
            let depth = self.deeper(depth)?;
            self.at += 1;
            let (b, hb) = self.unary(depth)?;
            let h = self.taller(ha, hb)?;
            return Ok((Expr::Bin(BinOp::Pow, Box::new(a), Box::new(b)), h));
        }
        Ok((a, ha))
    }

    fn expect(&mut self, c: char, what: &str) -> Result<()> {
        if self.peek() == Tok::Sym(c) {
            self.at += 1;
            Ok(())
        } else {
            self.fail(format!("expected {what}, found {}", self.found()))
        }
    }

    fn primary(&mut self, depth: usize) -> Result<(Expr, usize)> {
        match self.peek() {
            Tok::Num(v) => {
                self.at += 1;
                Ok((Expr::Num(v), 0))
            }
            Tok::Sym('(') => {
                let depth = self.deeper(depth)?;
                self.at += 1;
                let e = self.sum(depth)?;
                self.expect(')', "`)`")?;
                Ok(e)
            }
            Tok::Name(name) => {
                let column = self.column();
                self.at += 1;
                if self.peek() == Tok::Sym('(') {
                    let Some(&(_, f, arity)) = FUNCTIONS.iter().find(|(n, _, _)| *n == name) else {
                        return Err(error(
                            self.text,
                            column,
                            format!(
                                "unknown function `{name}`; the functions are {}",
                                list(FUNCTIONS.iter().map(|f| f.0))
                            ),
                        ));
                    };
                    let depth = self.deeper(depth)?;
                    self.at += 1;
                    let (first, mut h) = self.sum(depth)?;
                    let mut args = vec![first];
                    while self.peek() == Tok::Sym(',') {
                        self.at += 1;
                        let (a, ha) = self.sum(depth)?;
                        h = h.max(ha);
                        args.push(a);
                    }
                    if args.len() != arity {
                        return Err(error(
                            self.text,
                            column,
                            format!(
                                "`{name}` takes {arity} argument{}, found {}",
                                if arity == 1 { "" } else { "s" },
                                args.len()
                            ),
                        ));
                    }
                    self.expect(')', "`,` or `)`")?;
                    return Ok((Expr::Call(f, args), self.taller(h, 0)?));
                }
                if let Some(i) = self.names.iter().position(|n| *n == name) {
                    return Ok((Expr::Var(i), 0));
                }
                if let Some(&(_, c)) = CONSTANTS.iter().find(|(n, _)| *n == name) {
                    return Ok((Expr::Num(c), 0));
                }
                let reason = if FUNCTIONS.iter().any(|f| f.0 == name) {
                    format!("the function `{name}` needs its argument in parentheses")
                } else {
                    format!(
                        "unknown name `{name}`; the names are {}; the functions {}",
                        list(
                            self.names
                                .iter()
                                .copied()
                                .chain(CONSTANTS.iter().map(|c| c.0))
                        ),
                        list(FUNCTIONS.iter().map(|f| f.0))
                    )
                };
                Err(error(self.text, column, reason))
            }
            _ => self.fail(format!(
                "expected a number, a name or `(`, found {}",
                self.found()
            )),
        }
    }
}

fn list<'s>(names: impl Iterator<Item = &'s str>) -> String {
    names
        .map(|n| format!("`{n}`"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Parse `text` with the variable names `names` (coordinates, momenta, parameters, …); a name
/// that is both a variable and a constant (`pi`) is the variable.
///
/// # Errors
/// [`Error::Parse`] with the 1-based column: an input longer than [`MAX_LENGTH`] bytes, nested
/// deeper than [`MAX_DEPTH`] or higher than [`MAX_HEIGHT`], an unexpected character or token, a malformed or overflowing
/// number, an unknown name (the message lists the known ones), a function called with the wrong
/// number of arguments.
pub fn parse(text: &str, names: &[&str]) -> Result<Expr> {
    if text.len() > MAX_LENGTH {
        return Err(error(
            "",
            MAX_LENGTH + 1,
            format!(
                "the expression is {} bytes long; at most {MAX_LENGTH} are accepted",
                text.len()
            ),
        ));
    }
    let toks = lex(text)?;
    let mut p = Parser {
        text,
        toks,
        at: 0,
        names,
    };
    let (e, _) = p.sum(0)?;
    if p.peek() != Tok::End {
        return p.fail(format!(
            "expected an operator or the end, found {}",
            p.found()
        ));
    }
    Ok(e)
}

//! A tiny expression language for motion laws and centrodes: numbers, `phi`, `pi`, `+ - * / ^`
//! (right-associative power), unary minus, parentheses and `sin cos tan exp sqrt abs`.
//! Parsed once into a tree; evaluated and differentiated symbolically.

/// A parse error with the byte offset into the expression.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("bad expression at byte {offset}: {message} (in `{text}`)")]
pub struct ExprError {
    /// Byte offset of the problem.
    pub offset: usize,
    /// What was expected.
    pub message: String,
    /// The expression text.
    pub text: String,
}

/// Expression tree in the variable `phi` (radians).
#[derive(Debug, Clone, PartialEq)]
pub enum Expr {
    /// A constant.
    Num(f64),
    /// The variable φ.
    Phi,
    /// Sum.
    Add(Box<Expr>, Box<Expr>),
    /// Difference.
    Sub(Box<Expr>, Box<Expr>),
    /// Product.
    Mul(Box<Expr>, Box<Expr>),
    /// Quotient.
    Div(Box<Expr>, Box<Expr>),
    /// Power.
    Pow(Box<Expr>, Box<Expr>),
    /// Negation.
    Neg(Box<Expr>),
    /// Function call.
    Call(Func, Box<Expr>),
}

/// Supported functions.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Func {
    /// sin
    Sin,
    /// cos
    Cos,
    /// tan
    Tan,
    /// exp
    Exp,
    /// sqrt
    Sqrt,
    /// abs
    Abs,
    /// natural log (used by derivatives of powers)
    Ln,
}

/// Deepest nesting of parentheses, unary signs, powers and calls accepted by [`Expr::parse`]
/// (the parser, evaluator and derivative recurse on the tree; a bound keeps the stack safe).
pub const MAX_DEPTH: usize = 64;

/// Longest expression text accepted by [`Expr::parse`], bytes (bounds the tree, whose
/// symbolic derivative can grow quadratically with the length of a product chain).
pub const MAX_LEN: usize = 1024;

struct Parser<'a> {
    s: &'a [u8],
    i: usize,
    text: &'a str,
    depth: usize,
}

impl Parser<'_> {
    fn err(&self, message: &str) -> ExprError {
        ExprError {
            offset: self.i,
            message: message.to_string(),
            text: self.text.to_string(),
        }
    }
    /// Enters one nesting level, refusing input nested deeper than [`MAX_DEPTH`].
    fn enter(&mut self) -> Result<(), ExprError> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return Err(self.err(&format!("expression nested deeper than {MAX_DEPTH} levels")));
        }
        Ok(())
    }
    fn ws(&mut self) {
        while self.i < self.s.len() && self.s[self.i].is_ascii_whitespace() {
            self.i += 1;
        }
    }
    fn peek(&mut self) -> Option<u8> {
        self.ws();
        self.s.get(self.i).copied()
    }
    fn sum(&mut self) -> Result<Expr, ExprError> {
        let mut l = self.product()?;
        while let Some(c @ (b'+' | b'-')) = self.peek() {
            self.i += 1;
            let r = self.product()?;
            l = if c == b'+' {
                Expr::Add(l.into(), r.into())
            } else {
                Expr::Sub(l.into(), r.into())
            };
        }
        Ok(l)
    }
    fn product(&mut self) -> Result<Expr, ExprError> {
        let mut l = self.unary()?;
        while let Some(c @ (b'*' | b'/')) = self.peek() {
            self.i += 1;
            let r = self.unary()?;
            l = if c == b'*' {
                Expr::Mul(l.into(), r.into())
            } else {
                Expr::Div(l.into(), r.into())
            };
        }
        Ok(l)
    }
    fn unary(&mut self) -> Result<Expr, ExprError> {
        self.enter()?;
        let e = self.unary_inner();
        self.depth -= 1;
        e
    }
    fn unary_inner(&mut self) -> Result<Expr, ExprError> {
        match self.peek() {
            Some(b'-') => {
                self.i += 1;
                Ok(Expr::Neg(self.unary()?.into()))
            }
            Some(b'+') => {
                self.i += 1;
                self.unary()
            }
            _ => self.power(),
        }
    }
    fn power(&mut self) -> Result<Expr, ExprError> {
        let base = self.atom()?;
        if self.peek() == Some(b'^') {
            self.i += 1;
            let e = self.unary()?;
            return Ok(Expr::Pow(base.into(), e.into()));
        }
        Ok(base)
    }
    fn atom(&mut self) -> Result<Expr, ExprError> {
        match self.peek() {
            Some(b'(') => {
                self.i += 1;
                let e = self.sum()?;
                if self.peek() != Some(b')') {
                    return Err(self.err("expected `)`"));
                }
                self.i += 1;
                Ok(e)
            }
            Some(c) if c.is_ascii_digit() || c == b'.' => {
                let start = self.i;
                while self.i < self.s.len()
                    && (self.s[self.i].is_ascii_digit() || self.s[self.i] == b'.')
                {
                    self.i += 1;
                }
                if self.i < self.s.len() && (self.s[self.i] == b'e' || self.s[self.i] == b'E') {
                    let save = self.i;
                    self.i += 1;
                    if self.i < self.s.len() && (self.s[self.i] == b'+' || self.s[self.i] == b'-') {
                        self.i += 1;
                    }
                    if self.i < self.s.len() && self.s[self.i].is_ascii_digit() {
                        while self.i < self.s.len() && self.s[self.i].is_ascii_digit() {
                            self.i += 1;
                        }
                    } else {
                        self.i = save;
                    }
                }
                let t = &self.text[start..self.i];
                t.parse::<f64>().map(Expr::Num).map_err(|_| ExprError {
                    offset: start,
                    message: format!("`{t}` is not a number"),
                    text: self.text.to_string(),
                })
            }
            Some(c) if c.is_ascii_alphabetic() => {
                let start = self.i;
                while self.i < self.s.len()
                    && (self.s[self.i].is_ascii_alphanumeric() || self.s[self.i] == b'_')
                {
                    self.i += 1;
                }
                let name = &self.text[start..self.i];
                let f = match name {
                    "phi" => return Ok(Expr::Phi),
                    "pi" => return Ok(Expr::Num(std::f64::consts::PI)),
                    "sin" => Func::Sin,
                    "cos" => Func::Cos,
                    "tan" => Func::Tan,
                    "exp" => Func::Exp,
                    "sqrt" => Func::Sqrt,
                    "abs" => Func::Abs,
                    _ => {
                        return Err(ExprError {
                            offset: start,
                            message: format!(
                                "unknown name `{name}` (expected phi, pi, sin, cos, tan, exp, sqrt, abs)"
                            ),
                            text: self.text.to_string(),
                        });
                    }
                };
                if self.peek() != Some(b'(') {
                    return Err(self.err("expected `(` after a function name"));
                }
                let arg = self.atom()?;
                Ok(Expr::Call(f, arg.into()))
            }
            Some(_) => Err(self.err("expected a number, `phi`, `pi`, a function or `(`")),
            None => Err(self.err("unexpected end of expression")),
        }
    }
}

impl Expr {
    /// Parses `text`.
    ///
    /// # Errors
    /// [`ExprError`] with the byte offset: syntax, unknown names, text longer than [`MAX_LEN`]
    /// bytes or nested deeper than [`MAX_DEPTH`].
    pub fn parse(text: &str) -> Result<Self, ExprError> {
        if text.len() > MAX_LEN {
            return Err(ExprError {
                offset: MAX_LEN,
                message: format!("expression longer than {MAX_LEN} bytes"),
                text: text.chars().take(64).collect::<String>() + "…",
            });
        }
        let mut p = Parser {
            s: text.as_bytes(),
            i: 0,
            text,
            depth: 0,
        };
        let e = p.sum()?;
        if p.peek().is_some() {
            return Err(p.err("unexpected trailing input"));
        }
        Ok(e)
    }

    /// Value at `phi` (rad).
    #[must_use]
    pub fn eval(&self, phi: f64) -> f64 {
        match self {
            Expr::Num(v) => *v,
            Expr::Phi => phi,
            Expr::Add(a, b) => a.eval(phi) + b.eval(phi),
            Expr::Sub(a, b) => a.eval(phi) - b.eval(phi),
            Expr::Mul(a, b) => a.eval(phi) * b.eval(phi),
            Expr::Div(a, b) => a.eval(phi) / b.eval(phi),
            Expr::Pow(a, b) => a.eval(phi).powf(b.eval(phi)),
            Expr::Neg(a) => -a.eval(phi),
            Expr::Call(f, a) => {
                let x = a.eval(phi);
                match f {
                    Func::Sin => x.sin(),
                    Func::Cos => x.cos(),
                    Func::Tan => x.tan(),
                    Func::Exp => x.exp(),
                    Func::Sqrt => x.sqrt(),
                    Func::Abs => x.abs(),
                    Func::Ln => x.ln(),
                }
            }
        }
    }

    fn depends_on_phi(&self) -> bool {
        match self {
            Expr::Num(_) => false,
            Expr::Phi => true,
            Expr::Add(a, b)
            | Expr::Sub(a, b)
            | Expr::Mul(a, b)
            | Expr::Div(a, b)
            | Expr::Pow(a, b) => a.depends_on_phi() || b.depends_on_phi(),
            Expr::Neg(a) | Expr::Call(_, a) => a.depends_on_phi(),
        }
    }

    /// Symbolic derivative d/dφ.
    #[must_use]
    pub fn derivative(&self) -> Expr {
        use Expr::{Add, Call, Div, Mul, Neg, Num, Phi, Pow, Sub};
        let b = |e: Expr| Box::new(e);
        match self {
            Num(_) => Num(0.0),
            Phi => Num(1.0),
            Add(u, v) => Add(b(u.derivative()), b(v.derivative())),
            Sub(u, v) => Sub(b(u.derivative()), b(v.derivative())),
            Mul(u, v) => Add(
                b(Mul(b(u.derivative()), v.clone())),
                b(Mul(u.clone(), b(v.derivative()))),
            ),
            Div(u, v) => Div(
                b(Sub(
                    b(Mul(b(u.derivative()), v.clone())),
                    b(Mul(u.clone(), b(v.derivative()))),
                )),
                b(Mul(v.clone(), v.clone())),
            ),
            Pow(u, v) if !v.depends_on_phi() => Mul(
                b(Mul(
                    v.clone(),
                    b(Pow(u.clone(), b(Sub(v.clone(), b(Num(1.0)))))),
                )),
                b(u.derivative()),
            ),
            Pow(u, v) => Mul(
                b(self.clone()),
                b(Add(
                    b(Mul(b(v.derivative()), b(Call(Func::Ln, u.clone())))),
                    b(Div(b(Mul(v.clone(), b(u.derivative()))), u.clone())),
                )),
            ),
            Neg(u) => Neg(b(u.derivative())),
            Call(f, u) => {
                let du = b(u.derivative());
                let outer = match f {
                    Func::Sin => Call(Func::Cos, u.clone()),
                    Func::Cos => Neg(b(Call(Func::Sin, u.clone()))),
                    Func::Tan => {
                        let c = Call(Func::Cos, u.clone());
                        Div(b(Num(1.0)), b(Mul(b(c.clone()), b(c))))
                    }
                    Func::Exp => Call(Func::Exp, u.clone()),
                    Func::Sqrt => Div(b(Num(0.5)), b(Call(Func::Sqrt, u.clone()))),
                    Func::Abs => Div(u.clone(), b(Call(Func::Abs, u.clone()))),
                    Func::Ln => Div(b(Num(1.0)), u.clone()),
                };
                Mul(b(outer), du)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_and_differentiates() {
        let e = Expr::parse("phi - 0.08*sin(2*phi)").unwrap();
        let d = e.derivative();
        for x in [0.0, 0.3, 2.0] {
            assert!((e.eval(x) - (x - 0.08 * (2.0 * x).sin())).abs() < 1e-15);
            assert!((d.eval(x) - (1.0 - 0.16 * (2.0 * x).cos())).abs() < 1e-15);
        }
        let e = Expr::parse("-2^2 + sqrt(abs(phi))*exp(1) / tan(pi/4) + phi^phi").unwrap();
        let x = 1.7f64;
        let want =
            -4.0 + x.abs().sqrt() * 1f64.exp() / (std::f64::consts::PI / 4.0).tan() + x.powf(x);
        assert!((e.eval(x) - want).abs() < 1e-12);
        let h = 1e-6;
        let num = (e.eval(x + h) - e.eval(x - h)) / (2.0 * h);
        assert!((e.derivative().eval(x) - num).abs() < 1e-7);
        let e = Expr::parse("1.5e-1*cos(phi)").unwrap();
        assert!((e.eval(0.0) - 0.15).abs() < 1e-15);
    }

    #[test]
    fn reports_position_of_errors() {
        assert_eq!(Expr::parse("phi + foo(2)").unwrap_err().offset, 6);
        assert_eq!(Expr::parse("(phi + 1").unwrap_err().offset, 8);
        assert_eq!(Expr::parse("phi 2").unwrap_err().offset, 4);
        // Deep nesting is refused with a typed error instead of overflowing the stack.
        let deep = "(".repeat(MAX_DEPTH + 1) + "phi" + &")".repeat(MAX_DEPTH + 1);
        assert!(Expr::parse(&deep).unwrap_err().message.contains("nested"));
        let ok = "(".repeat(MAX_DEPTH - 1) + "phi" + &")".repeat(MAX_DEPTH - 1);
        assert_eq!(Expr::parse(&ok).unwrap(), Expr::Phi);
        assert!(Expr::parse(&"-".repeat(10_000)).is_err());
        assert!(
            Expr::parse(&"phi+".repeat(300))
                .unwrap_err()
                .message
                .contains("longer")
        );
    }
}

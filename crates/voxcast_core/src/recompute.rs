//! Recomputes the equations a text prints from the text's own numbers: every line of the form
//! `… = expression = result` whose expression holds only numbers, `(x, y, z)` triples, `+`,
//! `−`, `·`, `/` and brackets is evaluated and compared with its result.
//!
//! Numbers are read as intervals — a number printed by [`crate::numbers::sig`] stands for any
//! value within [`crate::numbers::half_width`] of it — and evaluated with interval arithmetic,
//! so the check is exact about rounding: it passes when the printed result could be the value
//! of the printed expression, and fails when no rounding explains the difference (the
//! breakdown once printed the front-to-back update filled with back-to-front numbers:
//! `0.3307 + (1 − 0.5115)·0.0365·0.831 = 0.3489`, whose right side is 0.3455).

use crate::numbers::half_width;

/// One printed equation that does not add up.
#[derive(Clone, Debug, PartialEq)]
pub struct Mismatch {
    pub line: String,
    pub why: String,
}

/// Checks every numeric equation in `text`; returns how many were checked, or the first that
/// does not add up. Public for the integration tests that check the levels' and docs' texts
/// (`cfg(test)` would hide it from them) and for anyone checking a text of their own.
pub fn check_equations(text: &str) -> Result<usize, Mismatch> {
    let mut checked = 0;
    for line in text.lines() {
        let parts: Vec<&str> = line.split(" = ").collect();
        if parts.len() < 3 {
            continue;
        }
        let (expr, result) = (parts[parts.len() - 2], parts[parts.len() - 1]);
        let (Some(lhs), Some(rhs)) = (parse(expr), parse(result)) else {
            continue; // words or symbols: not an equation with numbers
        };
        let fail = |why: String| Mismatch {
            line: line.to_string(),
            why,
        };
        if lhs.len() != rhs.len() && lhs.len() != 1 && rhs.len() != 1 {
            return Err(fail(format!("{} values against {}", lhs.len(), rhs.len())));
        }
        for i in 0..lhs.len().max(rhs.len()) {
            let (a, b) = (lhs[i.min(lhs.len() - 1)], rhs[i.min(rhs.len() - 1)]);
            // Slack for the f32 arithmetic behind the printed values.
            let slack = 1e-6 + 1e-5 * a.1.abs().max(b.1.abs());
            if a.1 + slack < b.0 || b.1 + slack < a.0 {
                return Err(fail(format!(
                    "component {i}: the expression gives [{}, {}], the result says [{}, {}]",
                    a.0, a.1, b.0, b.1
                )));
            }
        }
        checked += 1;
    }
    Ok(checked)
}

/// An interval `[lo, hi]`.
type Iv = (f64, f64);

/// Parses and evaluates `s`; `None` if it is not purely numeric.
fn parse(s: &str) -> Option<Vec<Iv>> {
    let tokens = tokenize(s.trim())?;
    let mut p = Parser { t: &tokens, i: 0 };
    let v = p.expr()?;
    (p.i == tokens.len()).then_some(v)
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Tok {
    Num(f64),
    Op(char),
}

fn tokenize(s: &str) -> Option<Vec<Tok>> {
    let chars: Vec<char> = s.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        if c == ' ' {
            i += 1;
        } else if "()+−·/,".contains(c) {
            out.push(Tok::Op(c));
            i += 1;
        } else if c.is_ascii_digit() || c == '-' {
            let start = i;
            i += 1;
            while i < chars.len()
                && (chars[i].is_ascii_digit()
                    || chars[i] == '.'
                    || chars[i] == 'e'
                    || (chars[i] == '-' && chars[i - 1] == 'e'))
            {
                i += 1;
            }
            let text: String = chars[start..i].iter().collect();
            out.push(Tok::Num(text.parse().ok()?));
        } else {
            return None;
        }
    }
    Some(out)
}

struct Parser<'t> {
    t: &'t [Tok],
    i: usize,
}

impl Parser<'_> {
    fn peek(&self) -> Option<Tok> {
        self.t.get(self.i).copied()
    }

    fn expr(&mut self) -> Option<Vec<Iv>> {
        let mut v = self.term()?;
        while let Some(Tok::Op(op @ ('+' | '−'))) = self.peek() {
            self.i += 1;
            let w = self.term()?;
            v = zip(&v, &w, |a, b| {
                if op == '+' {
                    (a.0 + b.0, a.1 + b.1)
                } else {
                    (a.0 - b.1, a.1 - b.0)
                }
            })?;
        }
        Some(v)
    }

    fn term(&mut self) -> Option<Vec<Iv>> {
        let mut v = self.factor()?;
        while let Some(Tok::Op(op @ ('·' | '/'))) = self.peek() {
            self.i += 1;
            let w = self.factor()?;
            v = zip(&v, &w, |a, b| {
                if op == '·' {
                    mul(a, b)
                } else if b.0 > 0.0 || b.1 < 0.0 {
                    mul(a, (1.0 / b.1, 1.0 / b.0))
                } else {
                    (f64::NEG_INFINITY, f64::INFINITY)
                }
            })?;
        }
        Some(v)
    }

    fn factor(&mut self) -> Option<Vec<Iv>> {
        match self.peek()? {
            Tok::Num(x) => {
                self.i += 1;
                let h = half_width(x);
                Some(vec![(x - h, x + h)])
            }
            Tok::Op('(') => {
                self.i += 1;
                let mut items = Vec::new();
                loop {
                    let v = self.expr()?;
                    if v.len() != 1 {
                        items.extend(v); // a bracketed vector expression
                    } else {
                        items.push(v[0]);
                    }
                    match self.peek()? {
                        Tok::Op(',') => self.i += 1,
                        Tok::Op(')') => {
                            self.i += 1;
                            return Some(items);
                        }
                        _ => return None,
                    }
                }
            }
            _ => None,
        }
    }
}

fn mul(a: Iv, b: Iv) -> Iv {
    let p = [a.0 * b.0, a.0 * b.1, a.1 * b.0, a.1 * b.1];
    (
        p.iter().copied().fold(f64::INFINITY, f64::min),
        p.iter().copied().fold(f64::NEG_INFINITY, f64::max),
    )
}

/// Applies `f` component-wise, a scalar broadcasting over a vector.
fn zip(a: &[Iv], b: &[Iv], f: impl Fn(Iv, Iv) -> Iv) -> Option<Vec<Iv>> {
    let n = a.len().max(b.len());
    if a.len() != n && a.len() != 1 || b.len() != n && b.len() != 1 {
        return None;
    }
    Some(
        (0..n)
            .map(|i| f(a[i.min(a.len() - 1)], b[i.min(b.len() - 1)]))
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn catches_the_formula_of_the_wrong_order() {
        // The breakdown's old line: front-to-back update, back-to-front numbers.
        let wrong = "C = 0.3307 + (1 − 0.5115)·0.0365·0.831 = 0.3489";
        assert!(check_equations(wrong).is_err());
        let right = "C = 0.3307 + (1 − 0.5115)·0.0365·0.831 = 0.3455";
        assert_eq!(check_equations(right), Ok(1));
    }

    #[test]
    fn vectors_broadcast_and_words_are_skipped() {
        let text = "Accumulate, sample 3:\n\
                    C_k = C_(k−1) + (1 − O_(k−1))·α_k·c_k\n\
                    C = (0.1, 0.2, 0.3) + (1 − 0.5)·0.5·(1, 0.4, 0) = (0.35, 0.3, 0.3)\n\
                    mean = 10 / 4 = 2.5";
        assert_eq!(check_equations(text), Ok(2));
        let bad = "C = (0.1, 0.2, 0.3) + (1 − 0.5)·0.5·(1, 0.4, 0) = (0.35, 0.31, 0.3)";
        assert!(check_equations(bad).is_err());
        assert_eq!(check_equations("x = -1.5e-3 · 2 = -3e-3"), Ok(1));
    }
}

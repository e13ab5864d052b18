//! Fixed-point decimal text of the output files (`{:.N}` without the exact-decimal machinery).
//!
//! The standard formatter prints the exact decimal value of a double rounded half-to-even, which
//! takes an arbitrary-precision fallback on hard cases; the CSV tables and SVG paths print
//! hundreds of thousands of numbers. Here `x·10ᴺ` is rounded to an integer (half away from
//! zero) and printed as digits: the same text as `{:.N}` except, rarely, a last digit on a near
//! tie (a difference of 10⁻ᴺ, far below what the columns resolve).
use std::fmt;

/// `x` with `decimals` digits after the point (at most 9); as `{:.N}` outside `|x·10ᴺ| < 2⁵³`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Fixed(pub f64, pub u32);

/// The decimal pairs `00`, `01`, …, `99`.
const PAIRS: &[u8; 200] = b"\
0001020304050607080910111213141516171819\
2021222324252627282930313233343536373839\
4041424344454647484950515253545556575859\
6061626364656667686970717273747576777879\
8081828384858687888990919293949596979899";

impl Fixed {
    /// The digits of `x·10ᴺ` rounded half away from zero, written backwards into `buf`: the
    /// text, or `None` outside `|x·10ᴺ| < 9·10¹⁵` (the caller then takes `{:.N}`). At most
    /// 16 + 1 + 9 + sign bytes.
    fn digits(self, buf: &mut [u8; 32]) -> Option<&str> {
        let (x, n) = (self.0, self.1.min(9));
        let scale = 10u64.pow(n);
        let y = (x * scale as f64).abs();
        if !(y < 9.0e15) {
            return None;
        }
        // Positive: the cast truncates, so this rounds half up.
        let v = (y + 0.5) as u64;
        let mut i = buf.len();
        let (mut int, mut frac) = (v / scale, v % scale);
        // Two digits per division, from a table of the pairs 00…99.
        fn put(buf: &mut [u8; 32], i: &mut usize, pair: u64) {
            let p = 2 * pair as usize;
            *i -= 2;
            buf[*i..*i + 2].copy_from_slice(&PAIRS[p..p + 2]);
        }
        for _ in 0..n / 2 {
            put(buf, &mut i, frac % 100);
            frac /= 100;
        }
        if n % 2 == 1 {
            i -= 1;
            buf[i] = b'0' + frac as u8;
        }
        if n > 0 {
            i -= 1;
            buf[i] = b'.';
        }
        while int >= 100 {
            put(buf, &mut i, int % 100);
            int /= 100;
        }
        if int >= 10 {
            put(buf, &mut i, int);
        } else {
            i -= 1;
            buf[i] = b'0' + int as u8;
        }
        if x.is_sign_negative() {
            i -= 1;
            buf[i] = b'-';
        }
        // ASCII digits, point and sign only.
        std::str::from_utf8(&buf[i..]).ok()
    }

    /// Appends the text to `out` — the same as through `Display`, without the formatting
    /// machinery's per-argument cost (the tables print four numbers a row).
    pub(crate) fn push_to(self, out: &mut String) {
        let mut buf = [0u8; 32];
        match self.digits(&mut buf) {
            Some(t) => out.push_str(t),
            None => {
                use fmt::Write as _;
                let _ = write!(out, "{:.*}", self.1.min(9) as usize, self.0);
            }
        }
    }
}

impl fmt::Display for Fixed {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut buf = [0u8; 32];
        match self.digits(&mut buf) {
            // One `write_str`: the formatting machinery's padding costs more than the digits.
            Some(t) => f.write_str(t),
            None => write!(f, "{:.*}", self.1.min(9) as usize, self.0),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Fixed;

    #[test]
    fn matches_the_standard_formatter_on_ordinary_values() {
        let mut differ = 0;
        for k in 0..200_000u32 {
            // Values across magnitudes and signs, none on an exact decimal tie.
            let x = (f64::from(k) * 0.618_033_988_749_894_9).sin() * 10f64.powi((k % 7) as i32 - 2);
            for n in [4u32, 6, 9] {
                if Fixed(x, n).to_string() != format!("{:.*}", n as usize, x) {
                    differ += 1;
                }
            }
        }
        // Near-ties may round the other way in the last digit: rare.
        assert!(differ < 30, "{differ} of 600000 differ");
        assert_eq!(Fixed(-0.0, 4).to_string(), format!("{:.4}", -0.0_f64));
        assert_eq!(Fixed(-0.00001, 4).to_string(), "-0.0000");
        assert_eq!(Fixed(12.5, 0).to_string(), "13");
        assert_eq!(Fixed(1e300, 3).to_string(), format!("{:.3}", 1e300));
        assert_eq!(Fixed(f64::NAN, 3).to_string(), "NaN");
        // `push_to` writes the same text.
        for x in [
            0.0,
            -0.0,
            1.5,
            -2.25e-7,
            123_456.789_012_345,
            1e300,
            f64::NAN,
        ] {
            let mut s = String::from("a");
            Fixed(x, 6).push_to(&mut s);
            assert_eq!(s, format!("a{}", Fixed(x, 6)));
        }
    }
}

//! The text form of a value: upper-case hex, as PostGIS prints geometry.

use crate::tin::TinError;

/// Upper-case hex of the storage bytes (text output, as PostGIS prints geometry).
pub fn to_hex(b: &[u8]) -> String {
    const D: &[u8; 16] = b"0123456789ABCDEF";
    let mut s = String::with_capacity(b.len() * 2);
    for &x in b {
        s.push(D[(x >> 4) as usize] as char);
        s.push(D[(x & 15) as usize] as char);
    }
    s
}

/// Parse hex text (either case) into bytes.
pub fn from_hex(s: &str) -> Result<Vec<u8>, TinError> {
    let s = s.trim();
    if !s.len().is_multiple_of(2) {
        return Err(TinError::corrupt("hex text has an odd number of digits"));
    }
    let val = |c: u8| -> Result<u8, TinError> {
        match c {
            b'0'..=b'9' => Ok(c - b'0'),
            b'a'..=b'f' => Ok(c - b'a' + 10),
            b'A'..=b'F' => Ok(c - b'A' + 10),
            _ => Err(TinError::corrupt(format!(
                "'{}' is not a hex digit",
                c as char
            ))),
        }
    };
    s.as_bytes()
        .chunks_exact(2)
        .map(|p| Ok(val(p[0])? << 4 | val(p[1])?))
        .collect()
}

//! Checkpoint files of the formats before `RSFCKPT5` — hand-written little-endian layouts —
//! read so that runs checkpointed by earlier versions still resume; never written (except
//! by the tests, which check that they are still read).
//!
//! Formats 3 and 4: magic, then `u64` dimension, step, and lengths of `u`, `alpha` and
//! `controller`, the `u64` step of the time origin (format 4: then the method's tag and its
//! number of values), the `f64` time of the time origin, time, τ and wall time, the `u64`
//! length of the fingerprint and its text (`field=value` lines), then `u`, `v`, `a`,
//! `alpha`, `controller` (format 4: and the method's values) as raw `f64` bits, and last
//! the CRC-32 (IEEE) of every byte before it. Format 2: no fingerprint, no wall time, no
//! checksum; format 1: also no time origin and no controller.

use std::borrow::Cow;

use super::fingerprint::Fingerprint;
use super::payload::Payload;

const MAGIC_V4: &[u8; 8] = b"RSFCKPT4";
const MAGIC_V3: &[u8; 8] = b"RSFCKPT3";
const MAGIC_V2: &[u8; 8] = b"RSFCKPT2";
const MAGIC_V1: &[u8; 8] = b"RSFCKPT1";

/// Fixed-size part of a format-3 file: magic, 6 words, 4 floats, fingerprint length.
const HEADER_V3: usize = 8 + 6 * 8 + 4 * 8 + 8;
/// Fixed-size part of a format-4 file: format 3's and two words (method tag, its length).
const HEADER_V4: usize = HEADER_V3 + 2 * 8;

/// The format (1–4) of a file that starts with `magic`, if it is one of these.
pub(super) fn version(magic: &[u8]) -> Option<u8> {
    match magic {
        m if m == MAGIC_V4 => Some(4),
        m if m == MAGIC_V3 => Some(3),
        m if m == MAGIC_V2 => Some(2),
        m if m == MAGIC_V1 => Some(1),
        _ => None,
    }
}

/// The content of a file of format `version` (from [`version`]).
///
/// # Errors
/// What is wrong, as text: truncated or oversized, a checksum mismatch (formats 3 and 4),
/// impossible sizes, a malformed fingerprint.
pub(super) fn parse(bytes: &[u8], version: u8) -> Result<Payload<'static>, String> {
    let body = if version >= 3 {
        let header = if version == 4 { HEADER_V4 } else { HEADER_V3 };
        super::checked_body(bytes, header)?
    } else {
        bytes
    };
    let header = match version {
        1 => 48,
        2 => 80,
        3 => HEADER_V3,
        _ => HEADER_V4,
    };
    if body.len() < header {
        return Err("truncated".into());
    }
    let word = |i: usize| {
        let mut w = [0u8; 8];
        w.copy_from_slice(&body[8 + 8 * i..16 + 8 * i]);
        u64::from_le_bytes(w)
    };
    let to_usize = |w: u64| usize::try_from(w).map_err(|_| "size overflow".to_string());
    let (dim, step, n, nf) = (word(0), word(1), to_usize(word(2))?, to_usize(word(3))?);
    // Format 4 has the method's tag and length after the sixth word.
    let w = |i: usize| {
        if version == 4 && i >= 6 {
            word(i + 2)
        } else {
            word(i)
        }
    };
    let (method_tag, nm) = if version == 4 {
        (word(6), to_usize(word(7))?)
    } else {
        (0, 0)
    };
    let (nc, time_origin, time, tau, wall_time_s, text_len) = match version {
        1 => {
            let tau = f64::from_bits(word(4));
            (0, (0, 0.0), step as f64 * tau, tau, 0.0, 0)
        }
        2 => (
            to_usize(word(4))?,
            (word(5), f64::from_bits(word(6))),
            f64::from_bits(word(7)),
            f64::from_bits(word(8)),
            0.0,
            0,
        ),
        _ => (
            to_usize(w(4))?,
            (w(5), f64::from_bits(w(6))),
            f64::from_bits(w(7)),
            f64::from_bits(w(8)),
            f64::from_bits(w(9)),
            to_usize(w(10))?,
        ),
    };
    let expected = n
        .checked_mul(24)
        .and_then(|x| x.checked_add(nf.checked_mul(8)?))
        .and_then(|x| x.checked_add(nc.checked_mul(8)?))
        .and_then(|x| x.checked_add(nm.checked_mul(8)?))
        .and_then(|x| x.checked_add(header))
        .and_then(|x| x.checked_add(text_len))
        .ok_or("size overflow")?;
    if body.len() != expected {
        return Err("truncated or oversized".into());
    }
    let fingerprint = std::str::from_utf8(&body[header..header + text_len])
        .ok()
        .and_then(Fingerprint::from_text)
        .ok_or("malformed fingerprint")?;
    let mut off = header + text_len;
    let mut take = |len: usize| {
        let out: Vec<f64> = body[off..off + 8 * len]
            .chunks_exact(8)
            .map(|c| f64::from_le_bytes(c.try_into().expect("8 bytes")))
            .collect();
        off += 8 * len;
        out
    };
    let (u, v, a, alpha, controller) = (take(n), take(n), take(n), take(nf), take(nc));
    let method = (method_tag, take(nm));
    Ok(Payload {
        dim,
        step,
        time_origin,
        time,
        tau,
        wall_time_s,
        fingerprint: Cow::Owned(fingerprint.0),
        u: Cow::Owned(u),
        v: Cow::Owned(v),
        a: Cow::Owned(a),
        alpha: Cow::Owned(alpha),
        controller,
        method,
    })
}

/// The bytes of `p` in format 3 (the implicit method, tag 0) or 4 (any other), as the
/// versions before `RSFCKPT5` wrote them: for the tests that check they are still read.
#[cfg(test)]
pub(super) fn to_bytes(p: &Payload<'_>) -> Vec<u8> {
    let text = Fingerprint(p.fingerprint.to_vec()).to_text();
    let (tag, method) = (&p.method.0, &p.method.1);
    let v4 = *tag != 0;
    let mut b = Vec::new();
    b.extend_from_slice(if v4 { MAGIC_V4 } else { MAGIC_V3 });
    for x in [
        p.dim,
        p.step,
        p.u.len() as u64,
        p.alpha.len() as u64,
        p.controller.len() as u64,
        p.time_origin.0,
    ] {
        b.extend_from_slice(&x.to_le_bytes());
    }
    if v4 {
        b.extend_from_slice(&tag.to_le_bytes());
        b.extend_from_slice(&(method.len() as u64).to_le_bytes());
    }
    for x in [p.time_origin.1, p.time, p.tau, p.wall_time_s] {
        b.extend_from_slice(&x.to_le_bytes());
    }
    b.extend_from_slice(&(text.len() as u64).to_le_bytes());
    b.extend_from_slice(text.as_bytes());
    for vec in [
        &p.u[..],
        &p.v[..],
        &p.a[..],
        &p.alpha[..],
        &p.controller,
        method,
    ] {
        for x in vec {
            b.extend_from_slice(&x.to_le_bytes());
        }
    }
    let crc = crc32fast::hash(&b);
    b.extend_from_slice(&crc.to_le_bytes());
    b
}

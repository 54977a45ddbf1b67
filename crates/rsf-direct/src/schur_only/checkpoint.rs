//! Checkpoints of the elimination: its position, the pending contribution blocks, the
//! accumulated kept block and right-hand sides, written atomically (a temporary file,
//! synced, renamed over the old one) and read back only for the same inputs.
//!
//! The file is little-endian 64-bit words: a header ([`Header`]), the stack, the packed
//! kept block, the right-hand sides, and a checksum of everything before it.

use std::fs::File;
use std::io::{BufReader, BufWriter, Read, Write};
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};

const MAGIC: u64 = u64::from_le_bytes(*b"RSFSCHUR");
const VERSION: u64 = 1;
const HEADER_WORDS: usize = 15;
/// Words per buffered read or write.
const CHUNK: usize = 1 << 16;

/// A 128-bit checksum of a stream of 64-bit words (two multiply–xorshift lanes; stable
/// across builds and platforms, not cryptographic: it tells inputs apart, it does not
/// resist forgery).
#[derive(Debug, Clone)]
pub(super) struct Checksum {
    a: u64,
    b: u64,
    len: u64,
}

impl Checksum {
    /// A checksum whose stream starts with `domain`.
    pub(super) fn new(domain: &str) -> Self {
        let mut h = Self {
            a: 0x243F_6A88_85A3_08D3,
            b: 0x1319_8A2E_0370_7344,
            len: 0,
        };
        h.bytes(domain.as_bytes());
        h
    }

    #[inline]
    pub(super) fn word(&mut self, w: u64) {
        self.a = (self.a ^ w).wrapping_mul(0x9E37_79B9_7F4A_7C15);
        self.a ^= self.a >> 29;
        self.b = (self.b.wrapping_add(w) ^ self.len).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        self.b ^= self.b >> 31;
        self.len = self.len.wrapping_add(1);
    }

    pub(super) fn words(&mut self, ws: impl IntoIterator<Item = u64>) {
        for w in ws {
            self.word(w);
        }
    }

    /// A length, then the values' bits.
    pub(super) fn f64s(&mut self, v: &[f64]) {
        self.word(v.len() as u64);
        self.words(v.iter().map(|x| x.to_bits()));
    }

    /// A length, then the values.
    pub(super) fn usizes(&mut self, v: &[usize]) {
        self.word(v.len() as u64);
        self.words(v.iter().map(|&x| x as u64));
    }

    /// A length, then the bytes in words.
    pub(super) fn bytes(&mut self, v: &[u8]) {
        self.word(v.len() as u64);
        for c in v.chunks(8) {
            let mut w = [0u8; 8];
            w[..c.len()].copy_from_slice(c);
            self.word(u64::from_le_bytes(w));
        }
    }

    pub(super) fn finish(&self) -> [u64; 2] {
        let mut a = self.a ^ self.len;
        a = (a ^ (a >> 33)).wrapping_mul(0xFF51_AFD7_ED55_8CCD);
        a ^= a >> 33;
        let mut b = self.b ^ self.len.rotate_left(17);
        b = (b ^ (b >> 33)).wrapping_mul(0xC4CE_B9FE_1A85_EC53);
        b ^= b >> 33;
        [a, b]
    }
}

/// What a checkpoint records besides the arrays.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Header {
    /// Checksum of the inputs (matrix, sets, right-hand sides, ordering).
    pub(super) inputs: [u64; 2],
    /// Checksum of the elimination order and the schedule.
    pub(super) layout: [u64; 2],
    /// Fronts of the schedule done.
    pub(super) done: usize,
    pub(super) stack_len: usize,
    pub(super) s_len: usize,
    pub(super) y_len: usize,
    /// Largest front and peak stack so far (entries), flops and seconds so far, and
    /// checkpoints written so far.
    pub(super) largest_front: usize,
    pub(super) peak_stack: usize,
    pub(super) flops: f64,
    pub(super) seconds: f64,
    pub(super) written: usize,
}

impl Header {
    fn words(&self) -> [u64; HEADER_WORDS] {
        [
            MAGIC,
            VERSION,
            self.inputs[0],
            self.inputs[1],
            self.layout[0],
            self.layout[1],
            self.done as u64,
            self.stack_len as u64,
            self.s_len as u64,
            self.y_len as u64,
            self.largest_front as u64,
            self.peak_stack as u64,
            self.flops.to_bits(),
            self.seconds.to_bits(),
            self.written as u64,
        ]
    }

    fn from_words(w: &[u64; HEADER_WORDS]) -> Option<Self> {
        (w[0] == MAGIC && w[1] == VERSION).then(|| Self {
            inputs: [w[2], w[3]],
            layout: [w[4], w[5]],
            done: w[6] as usize,
            stack_len: w[7] as usize,
            s_len: w[8] as usize,
            y_len: w[9] as usize,
            largest_front: w[10] as usize,
            peak_stack: w[11] as usize,
            flops: f64::from_bits(w[12]),
            seconds: f64::from_bits(w[13]),
            written: w[14] as usize,
        })
    }
}

fn io_err(path: &Path, e: impl std::fmt::Display) -> Error {
    Error::Checkpoint {
        path: path.display().to_string(),
        reason: e.to_string(),
    }
}

/// The temporary file a checkpoint is written to before it replaces `path`.
fn partial_path(path: &Path) -> PathBuf {
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(".partial");
    path.with_file_name(name)
}

/// Writes `header` and the arrays to `path` atomically: into `path.partial`, synced,
/// then renamed over `path` (a crash leaves the old checkpoint or the new one, never a
/// mix).
///
/// # Errors
/// [`Error::Checkpoint`] for a failed write or rename.
pub(super) fn write(path: &Path, header: &Header, arrays: [&[f64]; 3]) -> Result<()> {
    let tmp = partial_path(path);
    let file = File::create(&tmp).map_err(|e| io_err(&tmp, e))?;
    let mut out = BufWriter::with_capacity(8 * CHUNK, file);
    let mut sum = Checksum::new("rsf-direct checkpoint");
    let mut buf = Vec::with_capacity(8 * CHUNK);
    let mut put = |words: &mut dyn Iterator<Item = u64>,
                   out: &mut BufWriter<File>,
                   sum: &mut Checksum|
     -> std::io::Result<()> {
        loop {
            buf.clear();
            for w in (&mut *words).take(CHUNK) {
                sum.word(w);
                buf.extend_from_slice(&w.to_le_bytes());
            }
            if buf.is_empty() {
                return Ok(());
            }
            out.write_all(&buf)?;
        }
    };
    let result = (|| -> std::io::Result<()> {
        put(&mut header.words().into_iter(), &mut out, &mut sum)?;
        for a in arrays {
            put(&mut a.iter().map(|x| x.to_bits()), &mut out, &mut sum)?;
        }
        let [c0, c1] = sum.finish();
        out.write_all(&c0.to_le_bytes())?;
        out.write_all(&c1.to_le_bytes())?;
        let file = out.into_inner().map_err(|e| e.into_error())?;
        file.sync_all()
    })();
    if let Err(e) = result {
        let _ = std::fs::remove_file(&tmp);
        return Err(io_err(&tmp, e));
    }
    std::fs::rename(&tmp, path).map_err(|e| io_err(path, e))?;
    // The rename itself is durable once the directory is synced (best effort: not every
    // platform opens directories).
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        if let Ok(d) = File::open(dir) {
            let _ = d.sync_all();
        }
    }
    Ok(())
}

/// Bytes of a checkpoint file holding `words` 64-bit words of arrays: the header, the
/// arrays and the 16-byte checksum.
pub(super) fn file_bytes(words: f64) -> f64 {
    8.0 * (HEADER_WORDS as f64 + words) + 16.0
}

/// The disk space of a checkpoint of `bytes`, held before the work it will record: a file
/// of zeros at `path`'s temporary name ([`write`]'s, which truncates it and writes the
/// checkpoint into the space it gave back), removed when dropped if it is still there.
pub(super) struct Held {
    tmp: PathBuf,
}

/// Holds `bytes` of disk space for the checkpoint at `path` ([`Held`]).
///
/// # Errors
/// [`Error::Checkpoint`] naming the temporary file and the write's error (`No space left
/// on device` where the disk cannot hold it); nothing is left behind.
pub(super) fn hold(path: &Path, bytes: u64) -> Result<Held> {
    let held = Held {
        tmp: partial_path(path),
    };
    let fail = |e: std::io::Error| {
        io_err(
            &held.tmp,
            format!(
                "{e} (holding the {bytes} bytes of the finished checkpoint before the \
                 elimination)"
            ),
        )
    };
    let mut file = File::create(&held.tmp).map_err(fail)?;
    // Zeros written, not a sparse `set_len`: the filesystem allocates them.
    let zeros = vec![0u8; 8 * CHUNK];
    let mut left = bytes;
    while left > 0 {
        let n = left.min(zeros.len() as u64) as usize;
        file.write_all(&zeros[..n]).map_err(fail)?;
        left -= n as u64;
    }
    file.sync_all().map_err(fail)?;
    Ok(held)
}

impl Drop for Held {
    fn drop(&mut self) {
        // The checkpoint's writes rename the file away; what is left is the zeros.
        let _ = std::fs::remove_file(&self.tmp);
    }
}

/// An opened checkpoint whose header has been read.
pub(super) struct Reader {
    path: PathBuf,
    input: BufReader<File>,
    sum: Checksum,
    pub(super) header: Header,
}

/// Opens the checkpoint at `path`: `None` if there is no file.
///
/// # Errors
/// [`Error::Checkpoint`] if it cannot be read or is not a checkpoint of this version.
pub(super) fn open(path: &Path) -> Result<Option<Reader>> {
    let file = match File::open(path) {
        Ok(f) => f,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(io_err(path, e)),
    };
    let mut input = BufReader::with_capacity(8 * CHUNK, file);
    let mut sum = Checksum::new("rsf-direct checkpoint");
    let mut words = [0u64; HEADER_WORDS];
    let mut b = [0u8; 8];
    for w in words.iter_mut() {
        input
            .read_exact(&mut b)
            .map_err(|e| io_err(path, format!("header: {e}")))?;
        *w = u64::from_le_bytes(b);
        sum.word(*w);
    }
    let header = Header::from_words(&words).ok_or_else(|| {
        io_err(
            path,
            "not a checkpoint of this version of the Schur-only elimination",
        )
    })?;
    Ok(Some(Reader {
        path: path.to_path_buf(),
        input,
        sum,
        header,
    }))
}

impl Reader {
    /// Reads the arrays into `out` (each of its length, as the header says, checked by the
    /// caller) and verifies the checksum.
    ///
    /// # Errors
    /// [`Error::Checkpoint`] for a short or damaged file.
    pub(super) fn read_arrays(mut self, out: [&mut [f64]; 3]) -> Result<()> {
        let path = self.path.clone();
        let mut buf = vec![0u8; 8 * CHUNK];
        for a in out {
            for chunk in a.chunks_mut(CHUNK) {
                let bytes = &mut buf[..8 * chunk.len()];
                self.input
                    .read_exact(bytes)
                    .map_err(|e| io_err(&path, format!("data: {e}")))?;
                for (x, b) in chunk.iter_mut().zip(bytes.chunks_exact(8)) {
                    let w = u64::from_le_bytes(b.try_into().expect("8 bytes"));
                    self.sum.word(w);
                    *x = f64::from_bits(w);
                }
            }
        }
        let mut tail = [0u8; 16];
        self.input
            .read_exact(&mut tail)
            .map_err(|e| io_err(&path, format!("checksum: {e}")))?;
        let stored = [
            u64::from_le_bytes(tail[..8].try_into().expect("8 bytes")),
            u64::from_le_bytes(tail[8..].try_into().expect("8 bytes")),
        ];
        if stored != self.sum.finish() {
            return Err(io_err(&path, "damaged: its checksum does not match"));
        }
        let mut extra = [0u8; 1];
        if self.input.read(&mut extra).map_err(|e| io_err(&path, e))? != 0 {
            return Err(io_err(&path, "damaged: data after the checksum"));
        }
        Ok(())
    }
}

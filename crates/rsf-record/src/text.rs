//! From bytes to lines of text: the encoding (UTF-8, UTF-16, Windows-1252), line ends
//! (`\n`, `\r\n` and the old Mac's lone `\r` all become `\n`), and a bound on a line's length.

use std::io::{self, Read};

/// The encodings lab software writes records in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TextEncoding {
    /// UTF-8 (ASCII included), no byte-order mark.
    Utf8,
    /// UTF-8 with a byte-order mark (Excel's "CSV UTF-8").
    Utf8Bom,
    /// UTF-16, little-endian (Windows' "Unicode text"), with or without a byte-order mark.
    Utf16Le,
    /// UTF-16, big-endian.
    Utf16Be,
    /// Windows-1252 / Latin-1 (older Windows and LabVIEW exports: `µ` as one byte 0xB5).
    Windows1252,
}

impl TextEncoding {
    /// The name used in messages and JSON.
    pub fn name(self) -> &'static str {
        match self {
            Self::Utf8 => "UTF-8",
            Self::Utf8Bom => "UTF-8 with a byte-order mark",
            Self::Utf16Le => "UTF-16LE",
            Self::Utf16Be => "UTF-16BE",
            Self::Windows1252 => "Windows-1252",
        }
    }
}

/// Bytes looked at to tell the encoding.
pub(crate) const SNIFF_BYTES: usize = 4096;

/// A fault found while turning bytes into lines; carried through `io::Error` and the csv
/// reader back to [`crate::ReadError`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub(crate) enum TextFault {
    #[error("NUL byte")]
    Nul { line: u64 },
    #[error("line too long")]
    LineTooLong { line: u64 },
}

/// The encoding of a file from its first bytes, or the line of a NUL byte in a file that is
/// not UTF-16.
pub(crate) fn sniff(prefix: &[u8]) -> Result<TextEncoding, TextFault> {
    if prefix.starts_with(&[0xEF, 0xBB, 0xBF]) {
        return Ok(TextEncoding::Utf8Bom);
    }
    if prefix.starts_with(&[0xFF, 0xFE]) {
        return Ok(TextEncoding::Utf16Le);
    }
    if prefix.starts_with(&[0xFE, 0xFF]) {
        return Ok(TextEncoding::Utf16Be);
    }
    // UTF-16 without a mark: ASCII text has a NUL in every other byte
    let pairs = prefix.len() / 2;
    if pairs >= 2 {
        let nul_at = |k: usize| prefix.chunks_exact(2).filter(|c| c[k] == 0).count();
        let (even, odd) = (nul_at(0), nul_at(1));
        if odd * 10 >= pairs * 9 && even * 10 < pairs {
            return Ok(TextEncoding::Utf16Le);
        }
        if even * 10 >= pairs * 9 && odd * 10 < pairs {
            return Ok(TextEncoding::Utf16Be);
        }
    }
    if let Some(p) = prefix.iter().position(|&b| b == 0) {
        let line = 1 + prefix[..p].iter().filter(|&&b| b == b'\n').count() as u64;
        return Err(TextFault::Nul { line });
    }
    Ok(TextEncoding::Utf8)
}

/// A byte source decoded to UTF-8: UTF-16 is transcoded (`encoding_rs_io`); UTF-8 passes
/// unchanged without its byte-order mark (bytes that are not UTF-8 pass too: a header in
/// Windows-1252 is decoded line by line, numbers are ASCII in every encoding).
pub(crate) fn decoder<'a, R: Read + 'a>(mut inner: R, enc: TextEncoding) -> std::io::Result<Box<dyn Read + 'a>> {
    let forced = match enc {
        TextEncoding::Utf16Le => encoding_rs::UTF_16LE,
        TextEncoding::Utf16Be => encoding_rs::UTF_16BE,
        TextEncoding::Utf8Bom => {
            let mut bom = [0u8; 3];
            inner.read_exact(&mut bom)?;
            return Ok(Box::new(inner));
        }
        TextEncoding::Utf8 | TextEncoding::Windows1252 => return Ok(Box::new(inner)),
    };
    Ok(Box::new(encoding_rs_io::DecodeReaderBytesBuilder::new().encoding(Some(forced)).strip_bom(true).build(inner)))
}

/// Text of a line in the file's encoding: UTF-8 where it is valid, else Windows-1252.
pub(crate) fn decode_line(bytes: &[u8]) -> (String, bool) {
    match std::str::from_utf8(bytes) {
        Ok(s) => (s.to_string(), false),
        Err(_) => (encoding_rs::WINDOWS_1252.decode_without_bom_handling(bytes).0.into_owned(), true),
    }
}

/// Line ends to `\n`, NUL bytes and over-long lines refused; counts lines and remembers
/// whether the text ended with a line end (a last line without one may be cut).
pub(crate) struct Lines<R> {
    inner: R,
    prev_cr: bool,
    line_len: usize,
    /// 1-based line being read.
    pub(crate) line: u64,
    /// Whether the last byte passed on ended a line (true before any byte).
    pub(crate) ended_with_newline: bool,
}

impl<R: Read> Lines<R> {
    pub(crate) fn new(inner: R) -> Self {
        Self { inner, prev_cr: false, line_len: 0, line: 1, ended_with_newline: true }
    }
}

impl<R> Lines<R> {
    /// Refuses a line that grows by `more` bytes past the bound.
    fn check_length(&self, more: usize) -> io::Result<()> {
        if self.line_len + more > crate::MAX_LINE_BYTES {
            return Err(io::Error::new(io::ErrorKind::InvalidData, TextFault::LineTooLong { line: self.line }));
        }
        Ok(())
    }
}

impl<R: Read> Read for Lines<R> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        loop {
            let n = self.inner.read(buf)?;
            if n == 0 {
                return Ok(0);
            }
            // the common case, no `\r` and no NUL: line ends found by memchr, bytes untouched
            if !self.prev_cr && memchr::memchr2(b'\r', 0, &buf[..n]).is_none() {
                let mut start = 0;
                for p in memchr::memchr_iter(b'\n', &buf[..n]) {
                    self.check_length(p - start)?;
                    self.line += 1;
                    self.line_len = 0;
                    start = p + 1;
                }
                self.check_length(n - start)?;
                self.line_len += n - start;
                self.ended_with_newline = buf[n - 1] == b'\n';
                return Ok(n);
            }
            let mut w = 0;
            for r in 0..n {
                let mut b = buf[r];
                if std::mem::take(&mut self.prev_cr) && b == b'\n' {
                    continue;
                }
                if b == b'\r' {
                    b = b'\n';
                    self.prev_cr = true;
                }
                match b {
                    0 => return Err(io::Error::new(io::ErrorKind::InvalidData, TextFault::Nul { line: self.line })),
                    b'\n' => {
                        self.line += 1;
                        self.line_len = 0;
                    }
                    _ => {
                        self.line_len += 1;
                        if self.line_len > crate::MAX_LINE_BYTES {
                            return Err(io::Error::new(
                                io::ErrorKind::InvalidData,
                                TextFault::LineTooLong { line: self.line },
                            ));
                        }
                    }
                }
                buf[w] = b;
                w += 1;
            }
            if w > 0 {
                self.ended_with_newline = buf[w - 1] == b'\n';
                return Ok(w);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn through(bytes: &[u8]) -> io::Result<Vec<u8>> {
        let mut out = vec![];
        let mut l = Lines::new(bytes);
        l.read_to_end(&mut out)?;
        Ok(out)
    }

    #[test]
    fn line_ends_become_newlines() {
        assert_eq!(through(b"a\r\nb\rc\nd").unwrap(), b"a\nb\nc\nd");
        assert_eq!(through(b"a\r\r\nb").unwrap(), b"a\n\nb");
        assert_eq!(through(b"").unwrap(), b"");
    }

    #[test]
    fn nul_and_long_lines_are_refused() {
        let e = through(b"a\nb\0").unwrap_err();
        assert_eq!(e.get_ref().unwrap().downcast_ref::<TextFault>(), Some(&TextFault::Nul { line: 2 }));
        let long = vec![b'1'; crate::MAX_LINE_BYTES + 10];
        assert!(through(&long).is_err());
    }

    #[test]
    fn encodings_are_told_apart() {
        assert_eq!(sniff(b"time_s,mu\n1,2\n").unwrap(), TextEncoding::Utf8);
        assert_eq!(sniff(b"\xEF\xBB\xBFtime").unwrap(), TextEncoding::Utf8Bom);
        assert_eq!(sniff(b"\xFF\xFEt\0i\0").unwrap(), TextEncoding::Utf16Le);
        assert_eq!(sniff(b"t\0i\0m\0e\0").unwrap(), TextEncoding::Utf16Le);
        assert_eq!(sniff(b"\0t\0i\0m\0e").unwrap(), TextEncoding::Utf16Be);
        assert_eq!(sniff(&[0u8; 4096]), Err(TextFault::Nul { line: 1 }));
        assert_eq!(sniff(b"a\nb\n\0\0\0x"), Err(TextFault::Nul { line: 3 }));
    }
}

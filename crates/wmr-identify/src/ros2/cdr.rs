//! CDR as ROS 2 puts it on the wire and in its bags: little-endian plain CDR (XCDR1),
//! a 4-byte encapsulation header `00 01 00 00` (CDR_LE, options 0), then the fields in
//! order, each primitive aligned to its own size (at most 8) counted from the first byte
//! after the header. Strings: a u32 length counting the terminating NUL, the bytes, the
//! NUL. Sequences: a u32 element count, then the elements; fixed arrays: the elements alone.
//!
//! Written by hand rather than with a crate (`cdr`, `serde_rosmsg`, `ros2-client`): the
//! messages wmr writes need six primitives, and the writer must not allocate per message
//! (it appends to a buffer kept by the encoder). The reader ([`CdrReader`]) is the mirror
//! image, for reading ROS 2 logs back.

/// The encapsulation header of little-endian plain CDR.
pub const CDR_LE_HEADER: [u8; 4] = [0x00, 0x01, 0x00, 0x00];

/// Appends one CDR message to a buffer.
pub struct CdrWriter<'a> {
    buf: &'a mut Vec<u8>,
    /// Where the payload (after the header) starts in `buf`: alignment counts from here.
    origin: usize,
}

impl<'a> CdrWriter<'a> {
    /// Clears `buf` and starts a message in it (the encapsulation header).
    pub fn new(buf: &'a mut Vec<u8>) -> Self {
        buf.clear();
        buf.extend_from_slice(&CDR_LE_HEADER);
        let origin = buf.len();
        Self { buf, origin }
    }

    /// Pads with zeros to a multiple of `n` bytes from the payload's start.
    fn align(&mut self, n: usize) {
        let offset = self.buf.len() - self.origin;
        let pad = (n - offset % n) % n;
        self.buf.resize(self.buf.len() + pad, 0);
    }

    /// A `uint32`.
    pub fn u32(&mut self, v: u32) {
        self.align(4);
        self.buf.extend_from_slice(&v.to_le_bytes());
    }

    /// An `int32`.
    pub fn i32(&mut self, v: i32) {
        self.align(4);
        self.buf.extend_from_slice(&v.to_le_bytes());
    }

    /// A `float64`.
    pub fn f64(&mut self, v: f64) {
        self.align(8);
        self.buf.extend_from_slice(&v.to_le_bytes());
    }

    /// A `string`: length with the NUL, bytes, NUL.
    pub fn string(&mut self, s: &str) {
        self.u32(s.len() as u32 + 1);
        self.buf.extend_from_slice(s.as_bytes());
        self.buf.push(0);
    }

    /// The element count of a sequence (`T[]`), before its elements.
    pub fn len(&mut self, n: usize) {
        self.u32(n as u32);
    }

    /// A fixed array of `float64` (`float64[36]`): the elements alone.
    pub fn f64_array(&mut self, v: &[f64]) {
        for &x in v {
            self.f64(x);
        }
    }

    /// A sequence of `float64` (`float64[]`): the count, then the elements.
    pub fn f64_seq(&mut self, v: &[f64]) {
        self.len(v.len());
        self.f64_array(v);
    }

    /// A `builtin_interfaces/Time` of `ns` nanoseconds from the epoch (sec, nanosec);
    /// seconds beyond `i32::MAX` saturate.
    pub fn time(&mut self, ns: u64) {
        self.i32(i32::try_from(ns / 1_000_000_000).unwrap_or(i32::MAX));
        self.u32((ns % 1_000_000_000) as u32);
    }
}

/// Why a CDR message could not be read.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CdrError(pub String);

impl std::fmt::Display for CdrError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for CdrError {}

/// Reads one CDR message (plain CDR, little- or big-endian as its header says).
pub struct CdrReader<'a> {
    data: &'a [u8],
    pos: usize,
    little: bool,
}

impl<'a> CdrReader<'a> {
    /// Starts on `data`, header included; refuses encodings other than plain CDR.
    pub fn new(data: &'a [u8]) -> Result<Self, CdrError> {
        let header = data.get(..4).ok_or_else(|| CdrError("shorter than the 4-byte CDR header".into()))?;
        let little = match (header[0], header[1]) {
            (0x00, 0x00) => false,
            (0x00, 0x01) => true,
            (a, b) => return Err(CdrError(format!("encapsulation {a:02x} {b:02x} is not plain CDR (00 00 or 00 01)"))),
        };
        Ok(Self { data: &data[4..], pos: 0, little })
    }

    fn take<const N: usize>(&mut self) -> Result<[u8; N], CdrError> {
        self.pos = self.pos.div_ceil(N) * N;
        let bytes = self
            .data
            .get(self.pos..self.pos + N)
            .ok_or_else(|| CdrError(format!("message ends at byte {} of the payload", self.data.len())))?;
        self.pos += N;
        Ok(bytes.try_into().unwrap_or([0; N]))
    }

    /// A `uint32`.
    pub fn u32(&mut self) -> Result<u32, CdrError> {
        let b = self.take::<4>()?;
        Ok(if self.little { u32::from_le_bytes(b) } else { u32::from_be_bytes(b) })
    }

    /// An `int32`.
    pub fn i32(&mut self) -> Result<i32, CdrError> {
        self.u32().map(|v| v as i32)
    }

    /// A `float64`.
    pub fn f64(&mut self) -> Result<f64, CdrError> {
        let b = self.take::<8>()?;
        Ok(if self.little { f64::from_le_bytes(b) } else { f64::from_be_bytes(b) })
    }

    /// A `string` (its NUL dropped).
    pub fn string(&mut self) -> Result<String, CdrError> {
        let n = self.u32()? as usize;
        let bytes = self
            .data
            .get(self.pos..self.pos.saturating_add(n))
            .ok_or_else(|| CdrError(format!("a string of {n} bytes runs past the message's end")))?;
        self.pos += n;
        let text = bytes.strip_suffix(&[0]).unwrap_or(bytes);
        String::from_utf8(text.to_vec()).map_err(|_| CdrError("a string is not UTF-8".into()))
    }

    /// A sequence's element count; refuses one longer than the bytes left could hold.
    // Reads a count from the message (not the reader's size): no `is_empty` to pair with.
    #[allow(clippy::len_without_is_empty)]
    pub fn len(&mut self) -> Result<usize, CdrError> {
        let n = self.u32()? as usize;
        if n > self.data.len().saturating_sub(self.pos) {
            return Err(CdrError(format!("a sequence of {n} elements runs past the message's end")));
        }
        Ok(n)
    }

    /// A sequence of `float64`.
    pub fn f64_seq(&mut self) -> Result<Vec<f64>, CdrError> {
        let n = self.len()?;
        (0..n).map(|_| self.f64()).collect()
    }

    /// Skips `n` `float64`s (a fixed array such as a covariance).
    pub fn skip_f64(&mut self, n: usize) -> Result<(), CdrError> {
        for _ in 0..n {
            self.f64()?;
        }
        Ok(())
    }

    /// A `builtin_interfaces/Time` as ns from the epoch (negative seconds: 0).
    pub fn time(&mut self) -> Result<u64, CdrError> {
        let sec = self.i32()?;
        let nanosec = self.u32()?;
        Ok(u64::try_from(sec).unwrap_or(0) * 1_000_000_000 + u64::from(nanosec))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A `std_msgs/Header` {stamp 1.5 s, frame "odom"} then a float64 1.0, worked out by
    /// hand: header 00 01 00 00; sec 1 (4 bytes); nanosec 500,000,000 = 0x1DCD6500;
    /// string length 5 (with the NUL) at offset 8, "odom\0" at 12..17; the float64 aligned
    /// to 24 (pad 17..24 with zeros); 1.0 = 0x3FF0000000000000.
    #[test]
    fn header_then_float_as_worked_out_by_hand() {
        let mut buf = Vec::new();
        let mut w = CdrWriter::new(&mut buf);
        w.time(1_500_000_000);
        w.string("odom");
        w.f64(1.0);
        let want: &[u8] = &[
            0x00, 0x01, 0x00, 0x00, // encapsulation: CDR_LE
            0x01, 0x00, 0x00, 0x00, // sec = 1
            0x00, 0x65, 0xCD, 0x1D, // nanosec = 500,000,000
            0x05, 0x00, 0x00, 0x00, // length 5
            b'o', b'd', b'o', b'm', 0x00, // "odom\0" (payload 12..17)
            0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, // pad to payload offset 24
            0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xF0, 0x3F, // 1.0
        ];
        assert_eq!(buf, want);
    }

    /// Alignment counts from the payload, not from the buffer: a string of 1 byte + NUL
    /// ends at payload offset 6, so a uint32 goes at 8 and a float64 after it at 16.
    #[test]
    fn alignment_is_relative_to_the_payload() {
        let mut buf = Vec::new();
        let mut w = CdrWriter::new(&mut buf);
        w.string("a");
        w.u32(7);
        w.f64(-2.0);
        let want: &[u8] = &[
            0x00, 0x01, 0x00, 0x00, // header
            0x02, 0x00, 0x00, 0x00, b'a', 0x00, // "a\0", payload 0..6
            0x00, 0x00, // pad to 8
            0x07, 0x00, 0x00, 0x00, // 7 at 8..12
            0x00, 0x00, 0x00, 0x00, // pad to 16
            0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xC0, // -2.0
        ];
        assert_eq!(buf, want);
    }

    /// A sequence of two strings then a float64 sequence (JointState's start): count 2,
    /// "l\0" (len 2) at 8..10, pad to 12, "rr\0" (len 3) at 16..19, pad, count 1 at 20,
    /// pad to 24, the float64.
    #[test]
    fn sequences_as_worked_out_by_hand() {
        let mut buf = Vec::new();
        let mut w = CdrWriter::new(&mut buf);
        w.len(2);
        w.string("l");
        w.string("rr");
        w.f64_seq(&[0.5]);
        let want: &[u8] = &[
            0x00, 0x01, 0x00, 0x00, // header
            0x02, 0x00, 0x00, 0x00, // 2 names
            0x02, 0x00, 0x00, 0x00, b'l', 0x00, // "l\0", payload 4..10
            0x00, 0x00, // pad to 12
            0x03, 0x00, 0x00, 0x00, b'r', b'r', 0x00, // "rr\0", payload 12..19
            0x00, // pad to 20
            0x01, 0x00, 0x00, 0x00, // 1 element, 20..24
            0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xE0, 0x3F, // 0.5 at 24
        ];
        assert_eq!(buf, want);
    }

    #[test]
    fn reader_reads_back_what_the_writer_wrote() {
        let mut buf = Vec::new();
        let mut w = CdrWriter::new(&mut buf);
        w.time(3_000_000_007);
        w.string("base_link");
        w.f64_seq(&[1.0, f64::MIN_POSITIVE, -0.0]);
        w.f64(f64::NAN);
        let mut r = CdrReader::new(&buf).unwrap();
        assert_eq!(r.time().unwrap(), 3_000_000_007);
        assert_eq!(r.string().unwrap(), "base_link");
        let seq = r.f64_seq().unwrap();
        assert_eq!(
            seq.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
            [1.0f64, f64::MIN_POSITIVE, -0.0].map(f64::to_bits)
        );
        assert!(r.f64().unwrap().is_nan());
        assert!(r.f64().is_err(), "past the end is an error");
    }

    #[test]
    fn reader_reads_big_endian_and_refuses_other_encapsulations() {
        let data = [0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x2A];
        assert_eq!(CdrReader::new(&data).unwrap().u32().unwrap(), 42);
        assert!(CdrReader::new(&[0x00, 0x07, 0, 0]).is_err(), "XCDR2 / PL_CDR is refused");
        assert!(CdrReader::new(&[0x00]).is_err());
        // A sequence whose count is larger than the message: an error, not an allocation.
        let huge = [0x00, 0x01, 0x00, 0x00, 0xFF, 0xFF, 0xFF, 0xFF];
        assert!(CdrReader::new(&huge).unwrap().f64_seq().is_err());
    }
}

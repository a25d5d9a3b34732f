//! Semihosting (QEMU `-semihosting-config enable=on,target=native`): print a line, read
//! the command line and a host file, exit with a status.

use core::fmt::Write as _;

use cortex_m_semihosting::{debug, hio, nr, syscall, syscall1};

/// Prints one line on the host's standard output.
pub fn println(args: core::fmt::Arguments<'_>) {
    if let Ok(mut out) = hio::hstdout() {
        let _ = out.write_fmt(args);
        let _ = out.write_str("\n");
    }
}

/// Ends the emulation: status 0 when `ok`, 1 otherwise.
pub fn exit(ok: bool) -> ! {
    debug::exit(if ok { debug::EXIT_SUCCESS } else { debug::EXIT_FAILURE });
    crate::halt()
}

/// The semihosting command line (`-semihosting-config ...,arg=a,arg=b` gives "a b") in
/// `buf`, as a string.
pub fn cmdline(buf: &mut [u8]) -> Option<&str> {
    let mut block = [buf.as_mut_ptr() as usize, buf.len()];
    // SAFETY: the block points to `buf` and its length; the host writes at most that
    // into `buf`, and the command line's length into the block's second word.
    let r = unsafe { syscall1(nr::GET_CMDLINE, block.as_mut_ptr() as usize) };
    if r != 0 {
        return None;
    }
    core::str::from_utf8(&buf[..block[1].min(buf.len())]).ok()
}

/// A host file open for reading.
pub struct File(usize);

impl File {
    /// Opens `path` (without NUL; at most 255 bytes) in binary read mode.
    pub fn open(path: &str) -> Option<File> {
        let mut z = [0u8; 256];
        if path.len() >= z.len() {
            return None;
        }
        z[..path.len()].copy_from_slice(path.as_bytes());
        let block = [z.as_ptr() as usize, nr::open::R_BINARY, path.len()];
        // SAFETY: a NUL-terminated path and its length.
        let h = unsafe { syscall(nr::OPEN, &block) };
        if h == usize::MAX { None } else { Some(File(h)) }
    }

    /// Fills `buf` completely; false at the end of the file or on error.
    pub fn read_exact(&mut self, buf: &mut [u8]) -> bool {
        let block = [self.0, buf.as_mut_ptr() as usize, buf.len()];
        // SAFETY: the host writes at most buf.len() bytes into buf; returns bytes not read.
        let not_read = unsafe { syscall(nr::READ, &block) };
        not_read == 0
    }
}

impl Drop for File {
    fn drop(&mut self) {
        let block = [self.0];
        // SAFETY: closes the handle.
        unsafe { syscall(nr::CLOSE, &block) };
    }
}

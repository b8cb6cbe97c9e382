//! The C ABI of gbsurf (`libgbsurf.a`, `libgbsurf.so`): the only crate of the workspace with
//! `unsafe` code besides the cxx bridge of `gbsurf-openmesh`.
//!
//! Conventions (see `cpp/include/gbsurf.h`, generated from this module by cbindgen):
//! - every function is named `gbsurf_*`; every fallible function returns a `uint32_t` status
//!   (`GBSURF_OK` = 0 or one of the `GBSURF_ERR_*` codes) and leaves a thread-local message
//!   ([`gbsurf_last_error_message`]) naming the problem and the offending element;
//! - no panic crosses the boundary: every entry runs inside `boundary`, a panic becomes
//!   `GBSURF_ERR_PANIC` with the panic's message and location, and nothing is printed on the
//!   host's stderr (`boundary` installs a panic hook that is silent for the library's panics);
//! - no input is a C enum: methods, twist modes, weight forms are `uint32_t` constants, checked;
//! - handles are opaque (`GbsurfResult`), freed with their `*_free` function, which accepts NULL.

#![deny(unsafe_op_in_unsafe_fn)]

use std::cell::{Cell, RefCell};
use std::ffi::{c_char, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Once;

mod options;
mod result;
mod offsets;

pub use options::*;
pub use result::*;
pub use offsets::*;

// ---------------------------------------------------------------------------------------------
// Status codes
// ---------------------------------------------------------------------------------------------

/// Success.
pub const GBSURF_OK: u32 = 0;
/// A required pointer argument was NULL, or not aligned for its type (the message says which).
pub const GBSURF_ERR_NULL: u32 = 1;
/// A count does not match its array (e.g. positions not a multiple of 3, face sizes not summing
/// to the number of face indices).
pub const GBSURF_ERR_COUNT: u32 = 2;
/// An index is out of range (a face corner naming a missing vertex, a patch/side/curve index).
pub const GBSURF_ERR_INDEX: u32 = 3;
/// An input number is NaN or infinite.
pub const GBSURF_ERR_NAN: u32 = 4;
/// The mesh was rejected by validation (the message names the face, edge or vertex).
pub const GBSURF_ERR_INVALID_MESH: u32 = 5;
/// An option is out of range, or the options' `struct_size` is unknown.
pub const GBSURF_ERR_INVALID_OPTION: u32 = 6;
/// The progress callback asked to cancel.
pub const GBSURF_ERR_CANCELLED: u32 = 7;
/// An internal error (a caught panic; its message and location are in the error message, nothing
/// is printed on stderr); please report it.
pub const GBSURF_ERR_PANIC: u32 = 8;
/// A file could not be read or written, or could not be parsed.
pub const GBSURF_ERR_IO: u32 = 9;
/// A caller buffer is too small (the needed size is in the `*_len`/`written` output).
pub const GBSURF_ERR_CAPACITY: u32 = 10;
/// The element has no such data (e.g. the center of a ribbon-only patch).
pub const GBSURF_ERR_KIND: u32 = 11;
/// Surface construction failed for a valid mesh (message explains).
pub const GBSURF_ERR_CONSTRUCTION: u32 = 12;
/// The header a caller was compiled against and the library linked disagree on
/// `GBSURF_ABI_VERSION` (reported by wrappers that compare it with `gbsurf_abi_version()`, such
/// as gbsurf.hpp; the library itself never returns it).
pub const GBSURF_ERR_VERSION: u32 = 13;
/// The conversion would need more memory than `GbsurfOptions::max_memory_mb` allows (refused
/// before any work; the message names the estimate, the output vertex count, the limit and how to
/// raise it), or an output buffer could not be allocated.
pub const GBSURF_ERR_TOO_LARGE: u32 = 14;
/// The input geometry admits no result (exact offsets): a zero derivative or normal, coincident
/// points, an offset distance of zero, a singular point (the message names it).
pub const GBSURF_ERR_DEGENERATE: u32 = 15;

/// ABI version: incremented on every incompatible change of this header (3: `GbsurfOffsetReport`
/// gained `frame_seams` and `max_normal_angle_pn`, so its size changed; 4:
/// `GbsurfReport::input_self_intersections` may be `GBSURF_NOT_CHECKED`, a new meaning of a
/// field's values; 5: `GbsurfOptions` gained `middle`, so its size changed).
pub const GBSURF_ABI_VERSION: u32 = 5;

// ---------------------------------------------------------------------------------------------
// Error state and the panic boundary
// ---------------------------------------------------------------------------------------------

/// An error on its way to C: a status code and a message.
#[derive(Debug, Clone)]
pub(crate) struct FfiError {
    pub code: u32,
    pub message: String,
}

impl FfiError {
    pub(crate) fn new(code: u32, message: impl Into<String>) -> Self {
        Self {
            code,
            message: message.into(),
        }
    }
}

pub(crate) type FfiResult<T = ()> = Result<T, FfiError>;

thread_local! {
    static LAST_ERROR: RefCell<CString> = RefCell::new(CString::default());
}

fn set_last_error(message: &str) {
    // Interior NULs cannot appear in a C string: replace them.
    let c = CString::new(message.replace('\0', "\\0")).unwrap_or_default();
    // `try_with`: during thread exit (a C thread-local destructor calling the library) the
    // thread-local may already be gone; the message is then dropped instead of panicking in an
    // `extern "C"` function (which would abort the process).
    let _ = LAST_ERROR.try_with(|e| *e.borrow_mut() = c);
}

fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "unknown panic payload".to_string()
    }
}

thread_local! {
    /// How many entries this thread is inside (an entry may call the host back, through the
    /// progress callback, and the host may call another entry).
    static DEPTH: Cell<u32> = const { Cell::new(0) };
    /// Where the last panic inside an entry on this thread happened (`file:line`), recorded by
    /// the panic hook for the message of `boundary`.
    static PANIC_AT: RefCell<Option<String>> = const { RefCell::new(None) };
}

/// Entries running on any thread. A panic on a worker thread of the core's thread pool (rayon)
/// while one runs is the library's own: its payload reaches the entry through rayon.
static ACTIVE: AtomicUsize = AtomicUsize::new(0);

static PANIC_HOOK: Once = Once::new();

/// Installs, once, the panic hook that keeps the library's panics off the host's stderr: a
/// panic on a thread inside an entry (or on a worker of the core's thread pool while an entry
/// runs) only records its location for `boundary`, which returns it as `GBSURF_ERR_PANIC` with
/// the message; any other panic goes to the hook that was installed before.
///
/// A hook the host installs later replaces this one (the panic hook is global to the Rust
/// runtime, which in a C host is the library's own).
fn install_panic_hook() {
    PANIC_HOOK.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            let in_entry = DEPTH.try_with(|d| d.get() > 0).unwrap_or(false);
            let in_worker = ACTIVE.load(Ordering::SeqCst) > 0 && rayon::current_thread_index().is_some();
            if !(in_entry || in_worker) {
                return previous(info);
            }
            if in_entry {
                let at = info.location().map(|l| format!("{}:{}", l.file(), l.line()));
                let _ = PANIC_AT.try_with(|p| *p.borrow_mut() = at);
            }
        }));
    });
}

/// Marks the current thread as inside an entry while it lives.
struct InEntry;

impl InEntry {
    fn enter() -> Self {
        ACTIVE.fetch_add(1, Ordering::SeqCst);
        let _ = DEPTH.try_with(|d| d.set(d.get() + 1));
        InEntry
    }
}

impl Drop for InEntry {
    fn drop(&mut self) {
        let _ = DEPTH.try_with(|d| d.set(d.get().saturating_sub(1)));
        ACTIVE.fetch_sub(1, Ordering::SeqCst);
    }
}

/// Runs `f` at an entry point: catches panics (printing nothing: see [`install_panic_hook`]),
/// stores the message of an error, returns the code. The message of a successful call is cleared.
pub(crate) fn boundary(name: &str, f: impl FnOnce() -> FfiResult) -> u32 {
    install_panic_hook();
    let outcome = {
        let _inside = InEntry::enter();
        let _ = PANIC_AT.try_with(|p| p.borrow_mut().take());
        catch_unwind(AssertUnwindSafe(f))
    };
    match outcome {
        Ok(Ok(())) => {
            set_last_error("");
            GBSURF_OK
        }
        Ok(Err(e)) => {
            set_last_error(&format!("{name}: {}", e.message));
            e.code
        }
        Err(payload) => {
            let message = panic_message(payload.as_ref());
            let at = PANIC_AT.try_with(|p| p.borrow_mut().take()).ok().flatten();
            // A payload whose destructor panics again must not unwind out of the boundary
            // (rust-lang/rust#86027): drop it inside catch_unwind, leak a second payload.
            let _inside = InEntry::enter();
            if let Err(again) = catch_unwind(AssertUnwindSafe(move || drop(payload))) {
                std::mem::forget(again);
            }
            drop(_inside);
            let at = at.map(|a| format!(" (at {a})")).unwrap_or_default();
            set_last_error(&format!("{name}: internal error (panic): {message}{at}"));
            GBSURF_ERR_PANIC
        }
    }
}

/// The body of every `gbsurf_*_free`: NULL is a no-op, otherwise the box is dropped inside a
/// panic guard (a destructor never unwinds into the host).
///
/// # Safety
/// `handle` is NULL or came from `Box::into_raw` of a `Box<T>` and is not freed before.
pub(crate) unsafe fn free_handle<T>(handle: *mut T) {
    if handle.is_null() {
        return;
    }
    let _ = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: from Box::into_raw, not freed before (contract).
        drop(unsafe { Box::from_raw(handle) });
    }));
}

/// NULL and alignment check of a pointer argument (dereferencing or slicing a misaligned
/// pointer is undefined behaviour even where the hardware tolerates it).
fn check_ptr<T>(p: *const T, what: &str, arg: &str) -> FfiResult {
    if p.is_null() {
        Err(FfiError::new(
            GBSURF_ERR_NULL,
            format!("{what} `{arg}` is NULL"),
        ))
    } else if !p.is_aligned() {
        Err(FfiError::new(
            GBSURF_ERR_NULL,
            format!(
                "{what} `{arg}` = {p:p} is not aligned to {} bytes",
                std::mem::align_of::<T>()
            ),
        ))
    } else {
        Ok(())
    }
}

/// A NULL (and alignment) check naming the argument.
pub(crate) fn non_null<T>(p: *const T, arg: &str) -> FfiResult<*const T> {
    check_ptr(p, "argument", arg).map(|()| p)
}

/// A NULL (and alignment) check for an output pointer.
pub(crate) fn non_null_mut<T>(p: *mut T, arg: &str) -> FfiResult<*mut T> {
    check_ptr(p as *const T, "output argument", arg).map(|()| p)
}

/// Builds a slice from a C pointer and length; a NULL pointer is accepted only when `len == 0`
/// (and is never passed to `from_raw_parts`). A length whose byte size exceeds `isize::MAX`
/// (no real array is that large: `from_raw_parts` forbids it) is a count error.
///
/// # Safety
/// `p` must point to `len` readable values of `T` when non-null.
pub(crate) unsafe fn slice_arg<'a, T>(p: *const T, len: usize, arg: &str) -> FfiResult<&'a [T]> {
    if len == 0 {
        return Ok(&[]);
    }
    let fits = len
        .checked_mul(std::mem::size_of::<T>())
        .is_some_and(|bytes| bytes <= isize::MAX as usize);
    if !fits {
        return Err(FfiError::new(
            GBSURF_ERR_COUNT,
            format!("{arg}: length {len} is larger than any array can be"),
        ));
    }
    let p = non_null(p, arg)?;
    // SAFETY: the caller guarantees `len` readable elements at `p` (documented in the header).
    Ok(unsafe { std::slice::from_raw_parts(p, len) })
}

/// [`slice_arg`] for an output array: the same NULL, alignment and size checks, and the array must
/// not overlap any of `inputs` (byte ranges; writing into an input being read is undefined
/// behaviour), which is a count error naming both.
///
/// # Safety
/// `p` must point to `len` writable values of `T` when non-null, not otherwise referenced while
/// the returned slice lives.
pub(crate) unsafe fn slice_arg_mut<'a, T>(p: *mut T, len: usize, arg: &str, inputs: &[(&str, *const u8, usize)]) -> FfiResult<&'a mut [T]> {
    if len == 0 {
        return Ok(&mut []);
    }
    let bytes = len
        .checked_mul(std::mem::size_of::<T>())
        .filter(|&b| b <= isize::MAX as usize)
        .ok_or_else(|| FfiError::new(GBSURF_ERR_COUNT, format!("{arg}: length {len} is larger than any array can be")))?;
    let p = non_null_mut(p, arg)?;
    let (lo, hi) = (p as usize, (p as usize).saturating_add(bytes));
    for &(name, q, qbytes) in inputs {
        let (qlo, qhi) = (q as usize, (q as usize).saturating_add(qbytes));
        if qbytes > 0 && lo < qhi && qlo < hi {
            return Err(FfiError::new(GBSURF_ERR_COUNT, format!("{arg} overlaps the input `{name}`")));
        }
    }
    // SAFETY: `len` writable elements at `p`, not aliased (contract; overlap with the inputs
    // checked above).
    Ok(unsafe { std::slice::from_raw_parts_mut(p, len) })
}

// ---------------------------------------------------------------------------------------------
// Version and error queries
// ---------------------------------------------------------------------------------------------

static VERSION: &std::ffi::CStr = match std::ffi::CStr::from_bytes_with_nul(
    concat!(env!("CARGO_PKG_VERSION"), "\0").as_bytes(),
) {
    Ok(s) => s,
    Err(_) => panic!("version string"),
};

/// The library version as a static NUL-terminated string, e.g. "0.1.0". Never NULL.
#[no_mangle]
pub extern "C" fn gbsurf_version() -> *const c_char {
    VERSION.as_ptr()
}

/// The ABI version this library implements (compare with `GBSURF_ABI_VERSION` from the header).
#[no_mangle]
pub extern "C" fn gbsurf_abi_version() -> u32 {
    GBSURF_ABI_VERSION
}

/// The message of the last failed call on this thread ("" after a successful call), as a
/// NUL-terminated UTF-8 string. Valid until the next `gbsurf_*` call on this thread. Never NULL.
#[no_mangle]
pub extern "C" fn gbsurf_last_error_message() -> *const c_char {
    LAST_ERROR
        .try_with(|e| e.borrow().as_ptr())
        .unwrap_or(c"".as_ptr())
}

/// The length in bytes (without the terminating NUL) of [`gbsurf_last_error_message`].
#[no_mangle]
pub extern "C" fn gbsurf_last_error_length() -> usize {
    LAST_ERROR
        .try_with(|e| e.borrow().as_bytes().len())
        .unwrap_or(0)
}

/// Copies the last error message into `buf` (NUL-terminated, truncated to `capacity - 1` bytes).
/// Returns the full message length in bytes (without NUL), so a caller can retry with a larger
/// buffer. `buf` may be NULL when `capacity` is 0. Does not change the stored message.
///
/// # Safety
/// `buf` must point to `capacity` writable bytes when `capacity > 0`.
#[no_mangle]
pub unsafe extern "C" fn gbsurf_last_error_copy(buf: *mut c_char, capacity: usize) -> usize {
    let r = catch_unwind(|| {
        LAST_ERROR.try_with(|e| {
            let e = e.borrow();
            let bytes = e.as_bytes();
            if capacity > 0 && !buf.is_null() {
                let n = bytes.len().min(capacity - 1);
                // SAFETY: `buf` has `capacity` > n bytes (caller contract); the regions are distinct.
                unsafe {
                    std::ptr::copy_nonoverlapping(bytes.as_ptr() as *const c_char, buf, n);
                    *buf.add(n) = 0;
                }
            }
            bytes.len()
        })
    });
    r.ok().and_then(|r| r.ok()).unwrap_or(0)
}

/// A static name for a status code, e.g. "GBSURF_ERR_NULL" ("GBSURF_ERR_UNKNOWN" for codes this
/// library does not define). Never NULL.
#[no_mangle]
pub extern "C" fn gbsurf_status_name(status: u32) -> *const c_char {
    let s: &'static [u8] = match status {
        GBSURF_OK => b"GBSURF_OK\0",
        GBSURF_ERR_NULL => b"GBSURF_ERR_NULL\0",
        GBSURF_ERR_COUNT => b"GBSURF_ERR_COUNT\0",
        GBSURF_ERR_INDEX => b"GBSURF_ERR_INDEX\0",
        GBSURF_ERR_NAN => b"GBSURF_ERR_NAN\0",
        GBSURF_ERR_INVALID_MESH => b"GBSURF_ERR_INVALID_MESH\0",
        GBSURF_ERR_INVALID_OPTION => b"GBSURF_ERR_INVALID_OPTION\0",
        GBSURF_ERR_CANCELLED => b"GBSURF_ERR_CANCELLED\0",
        GBSURF_ERR_PANIC => b"GBSURF_ERR_PANIC\0",
        GBSURF_ERR_IO => b"GBSURF_ERR_IO\0",
        GBSURF_ERR_CAPACITY => b"GBSURF_ERR_CAPACITY\0",
        GBSURF_ERR_KIND => b"GBSURF_ERR_KIND\0",
        GBSURF_ERR_CONSTRUCTION => b"GBSURF_ERR_CONSTRUCTION\0",
        GBSURF_ERR_VERSION => b"GBSURF_ERR_VERSION\0",
        GBSURF_ERR_TOO_LARGE => b"GBSURF_ERR_TOO_LARGE\0",
        GBSURF_ERR_DEGENERATE => b"GBSURF_ERR_DEGENERATE\0",
        _ => b"GBSURF_ERR_UNKNOWN\0",
    };
    s.as_ptr() as *const c_char
}

#[cfg(test)]
mod tests;

#[cfg(test)]
mod boundary_tests {
    use super::*;
    use std::ffi::CStr;

    fn last() -> String {
        // SAFETY: gbsurf_last_error_message never returns NULL and the string lives until the
        // next call on this thread.
        unsafe { CStr::from_ptr(gbsurf_last_error_message()) }
            .to_string_lossy()
            .into_owned()
    }

    #[test]
    fn boundary_catches_panics_and_keeps_messages() {
        let code = boundary("f", || panic!("boom {}", 3));
        assert_eq!(code, GBSURF_ERR_PANIC);
        assert!(last().contains("boom 3"), "{}", last());
        let code = boundary("g", || Err(FfiError::new(GBSURF_ERR_INDEX, "face 4")));
        assert_eq!(code, GBSURF_ERR_INDEX);
        assert_eq!(last(), "g: face 4");
        assert_eq!(gbsurf_last_error_length(), "g: face 4".len());
        assert_eq!(boundary("h", || Ok(())), GBSURF_OK);
        assert_eq!(last(), "");
    }

    /// The child of [`no_panic_text_reaches_stderr`] (does nothing unless run as that child).
    /// Mode `inside`: panics inside entries, on this thread, in a nested entry and on a worker
    /// thread of the core's pool, all caught silently. Mode `outside`: a panic outside any entry,
    /// after the hook is installed, which the previous hook must still print.
    #[test]
    #[ignore = "run as a child process by no_panic_text_reaches_stderr"]
    fn panicking_entries_child() {
        use rayon::prelude::*;
        match std::env::var("GBSURF_PANIC_CHILD").as_deref() {
            Ok("inside") => {
                assert_eq!(boundary("f", || panic!("boom {}", 3)), GBSURF_ERR_PANIC);
                assert!(last().starts_with("f: internal error (panic): boom 3 (at capi/src/lib.rs:"), "{}", last());
                let code = boundary("outer", || {
                    let inner = boundary("inner", || panic!("nested"));
                    assert_eq!(inner, GBSURF_ERR_PANIC);
                    assert!(last().contains("inner: internal error (panic): nested"), "{}", last());
                    Ok(())
                });
                assert_eq!(code, GBSURF_OK);
                let code = boundary("pool", || {
                    (0..64).into_par_iter().for_each(|i| assert!(i != 37, "worker {i}"));
                    Ok(())
                });
                assert_eq!(code, GBSURF_ERR_PANIC);
                assert!(last().contains("worker 37"), "{}", last());
            }
            Ok("outside") => {
                assert_eq!(boundary("ok", || Ok(())), GBSURF_OK);
                assert!(std::panic::catch_unwind(|| panic!("outside boom")).is_err());
            }
            _ => {}
        }
    }

    #[test]
    fn no_panic_text_reaches_stderr() {
        let run = |mode: &str| {
            std::process::Command::new(std::env::current_exe().unwrap())
                .args(["--exact", "boundary_tests::panicking_entries_child", "--ignored", "--nocapture", "--test-threads=1"])
                .env("GBSURF_PANIC_CHILD", mode)
                .env_remove("RUST_BACKTRACE")
                .output()
                .unwrap()
        };
        let inside = run("inside");
        let stdout = String::from_utf8_lossy(&inside.stdout);
        assert!(inside.status.success() && stdout.contains("1 passed"), "{stdout}");
        assert_eq!(String::from_utf8_lossy(&inside.stderr), "");
        // The control: the test can see a panic that is printed.
        let outside = run("outside");
        assert!(outside.status.success(), "{}", String::from_utf8_lossy(&outside.stdout));
        assert!(String::from_utf8_lossy(&outside.stderr).contains("outside boom"), "{outside:?}");
    }

    #[test]
    fn a_panic_payload_that_panics_when_dropped_stays_inside() {
        struct Bomb;
        impl Drop for Bomb {
            fn drop(&mut self) {
                panic!("payload destructor");
            }
        }
        let code = boundary("bomb", || std::panic::resume_unwind(Box::new(Bomb)));
        assert_eq!(code, GBSURF_ERR_PANIC);
        assert!(last().contains("bomb: internal error"), "{}", last());
    }

    #[test]
    fn error_copy_truncates_and_reports_full_length() {
        boundary("copy", || {
            Err(FfiError::new(GBSURF_ERR_COUNT, "0123456789"))
        });
        let full = "copy: 0123456789";
        let mut buf = [1 as c_char; 8];
        // SAFETY: buf has 8 writable bytes.
        let n = unsafe { gbsurf_last_error_copy(buf.as_mut_ptr(), buf.len()) };
        assert_eq!(n, full.len());
        // SAFETY: the copy is NUL-terminated within the buffer.
        let got = unsafe { CStr::from_ptr(buf.as_ptr()) }
            .to_str()
            .unwrap()
            .to_string();
        assert_eq!(got, &full[..7]);
        // SAFETY: capacity 0 with NULL is allowed.
        assert_eq!(
            unsafe { gbsurf_last_error_copy(std::ptr::null_mut(), 0) },
            full.len()
        );
    }

    #[test]
    fn status_names_are_distinct() {
        let names: Vec<String> = (0..=16)
            // SAFETY: static NUL-terminated strings.
            .map(|c| {
                unsafe { CStr::from_ptr(gbsurf_status_name(c)) }
                    .to_string_lossy()
                    .into_owned()
            })
            .collect();
        assert_eq!(names[0], "GBSURF_OK");
        assert_eq!(names[13], "GBSURF_ERR_VERSION");
        assert_eq!(names[14], "GBSURF_ERR_TOO_LARGE");
        assert_eq!(names[15], "GBSURF_ERR_DEGENERATE");
        assert_eq!(names[16], "GBSURF_ERR_UNKNOWN");
        let mut uniq = names[..16].to_vec();
        uniq.sort();
        uniq.dedup();
        assert_eq!(uniq.len(), 16);
    }
}

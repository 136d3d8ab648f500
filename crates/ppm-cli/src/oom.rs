//! An allocation that fails ends the process with an error and exit status 1, not SIGABRT.
//!
//! The memory check ([`crate::memory`]) refuses a render that cannot fit before it starts,
//! naming the setting to lower. What it cannot foresee (another process taking the memory
//! meanwhile, a buffer that grows with the scene, `PPM_MEMORY_LIMIT` set above the real
//! limit) still fails inside the allocator, where Rust's default is to print "memory
//! allocation of N bytes failed" and abort: a signal, which a batch system reports as a crash
//! and which leaves no hint of which limit was hit. This allocator forwards to the system's
//! and, when it returns nothing, writes an error naming the bytes and the process's limits
//! and exits with status 1.
//!
//! The report is written without allocating (a fixed buffer and `write(2)`), and the process
//! ends with `_exit`: nothing that could allocate again runs after the failure.

use std::alloc::{GlobalAlloc, Layout, System};
use std::fmt::Write;
use std::sync::atomic::{AtomicU8, Ordering};

/// What the process is doing, so that a failed allocation names the buffers it was making.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub enum Phase {
    /// Reading the scene, building its BVH.
    Loading = 0,
    /// Making the render state.
    Starting = 1,
    /// Rendering iterations.
    Rendering = 2,
    /// Writing the images and the saved state.
    Writing = 3,
}

impl Phase {
    /// The buffers this phase allocates, in words.
    fn buffers(self) -> &'static str {
        match self {
            Phase::Loading => "loading the scene (its meshes, textures and BVH)",
            Phase::Starting => {
                "allocating the render state (the film, the photon buffer and hash grid, \
                 per-pixel statistics, vcm's light subpath storage)"
            }
            Phase::Rendering => {
                "rendering an iteration (the photon buffer and hash grid, and vcm's light \
                 subpaths, grow with what the iteration stores)"
            }
            Phase::Writing => "writing the images and the render state",
        }
    }

    fn from_u8(v: u8) -> Phase {
        match v {
            1 => Phase::Starting,
            2 => Phase::Rendering,
            3 => Phase::Writing,
            _ => Phase::Loading,
        }
    }
}

static PHASE: AtomicU8 = AtomicU8::new(Phase::Loading as u8);

/// Records what the process does from now on (see [`Phase`]).
pub fn set_phase(phase: Phase) {
    PHASE.store(phase as u8, Ordering::Relaxed);
}

/// The system allocator, with [`out_of_memory`] where it fails.
pub struct ReportingAllocator;

// SAFETY: every call is forwarded unchanged to `System`; a null result ends the process.
unsafe impl GlobalAlloc for ReportingAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // SAFETY: the caller's contract is System's.
        let p = unsafe { System.alloc(layout) };
        if p.is_null() {
            out_of_memory(layout.size());
        }
        p
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        // SAFETY: as above.
        let p = unsafe { System.alloc_zeroed(layout) };
        if p.is_null() {
            out_of_memory(layout.size());
        }
        p
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // SAFETY: as above.
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        if p.is_null() {
            out_of_memory(new_size);
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: as above.
        unsafe { System.dealloc(ptr, layout) }
    }
}

/// A message built in place, cut at the buffer's end.
struct Message {
    bytes: [u8; 1024],
    len: usize,
}

impl Write for Message {
    fn write_str(&mut self, s: &str) -> std::fmt::Result {
        let n = s.len().min(self.bytes.len() - self.len);
        self.bytes[self.len..self.len + n].copy_from_slice(&s.as_bytes()[..n]);
        self.len += n;
        Ok(())
    }
}

/// Writes why the allocation of `size` bytes failed to stderr and exits with status 1.
fn out_of_memory(size: usize) -> ! {
    let mut m = Message {
        bytes: [0; 1024],
        len: 0,
    };
    let _ = write!(
        m,
        "error: out of memory: allocating {size} bytes ({:.2} GiB) failed while {}",
        size as f64 / 1073741824.0,
        Phase::from_u8(PHASE.load(Ordering::Relaxed)).buffers()
    );
    let limits = [
        (libc::RLIMIT_AS, "ulimit -v (RLIMIT_AS)"),
        (libc::RLIMIT_DATA, "ulimit -d (RLIMIT_DATA)"),
    ];
    let mut any = false;
    for (resource, name) in limits {
        let mut limit = libc::rlimit {
            rlim_cur: 0,
            rlim_max: 0,
        };
        // SAFETY: getrlimit writes one rlimit through the valid pointer it is given (and
        // does not allocate).
        let ok = unsafe { libc::getrlimit(resource, &mut limit) } == 0;
        if ok && limit.rlim_cur != libc::RLIM_INFINITY {
            let gib = limit.rlim_cur as f64 / 1073741824.0;
            let _ = write!(
                m,
                "{} the process's {name} is {gib:.2} GiB",
                if any { " and" } else { ";" }
            );
            any = true;
        }
    }
    if !any {
        let _ = write!(m, "; the machine's memory or a cgroup memory limit ran out");
    }
    let _ = writeln!(
        m,
        "; lower --photons or the resolution (--width/--height), or raise the limit"
    );
    // SAFETY: writes the initialised part of the buffer to stderr, then ends the process
    // without running anything that could allocate.
    unsafe {
        libc::write(2, m.bytes.as_ptr().cast(), m.len);
        libc::_exit(1)
    }
}

//! Small `memcpy`, `memmove` and `memset` for the MCU, with the ARM EABI's `__aeabi_mem*`
//! entry points. compiler-builtins' are unrolled for speed and take 1.6 KiB of the firmware's
//! flash; the firmware moves a few hundred bytes at a time (a run's settings, a line of text),
//! for which a word at a time is fast enough. On the MCU they replace compiler-builtins' weak
//! definitions at link time; on the host only the copy and fill routines exist, for the tests.
//!
//! Every access is volatile, so that the compiler cannot take the loops for copies and call
//! these very functions from inside them.
#![no_std]

use core::ptr::{read_volatile, write_volatile};

/// Copies `n` bytes from `src` to `dest`; the two may overlap.
///
/// # Safety
/// `src` must be valid for reading and `dest` for writing `n` bytes.
pub unsafe fn copy(dest: *mut u8, src: *const u8, n: usize) {
    // Words when both sides share their alignment.
    let words = (dest as usize ^ src as usize) & 3 == 0;
    // Safety (all blocks): every offset is below `n`, as the caller promises.
    unsafe {
        if (dest as usize) <= (src as usize) {
            let mut i = 0;
            if words {
                while i < n && (dest as usize + i) & 3 != 0 {
                    write_volatile(dest.add(i), read_volatile(src.add(i)));
                    i += 1;
                }
                while n - i >= 4 {
                    write_volatile(dest.add(i).cast::<u32>(), read_volatile(src.add(i).cast::<u32>()));
                    i += 4;
                }
            }
            while i < n {
                write_volatile(dest.add(i), read_volatile(src.add(i)));
                i += 1;
            }
        } else {
            // Overlapping with `dest` above `src`: from the end.
            let mut i = n;
            if words {
                while i > 0 && (dest as usize + i) & 3 != 0 {
                    i -= 1;
                    write_volatile(dest.add(i), read_volatile(src.add(i)));
                }
                while i >= 4 {
                    i -= 4;
                    write_volatile(dest.add(i).cast::<u32>(), read_volatile(src.add(i).cast::<u32>()));
                }
            }
            while i > 0 {
                i -= 1;
                write_volatile(dest.add(i), read_volatile(src.add(i)));
            }
        }
    }
}

/// Sets `n` bytes at `dest` to `byte`.
///
/// # Safety
/// `dest` must be valid for writing `n` bytes.
pub unsafe fn fill(dest: *mut u8, byte: u8, n: usize) {
    let word = u32::from_ne_bytes([byte; 4]);
    let mut i = 0;
    // Safety: every offset is below `n`, as the caller promises.
    unsafe {
        while i < n && (dest as usize + i) & 3 != 0 {
            write_volatile(dest.add(i), byte);
            i += 1;
        }
        while n - i >= 4 {
            write_volatile(dest.add(i).cast::<u32>(), word);
            i += 4;
        }
        while i < n {
            write_volatile(dest.add(i), byte);
            i += 1;
        }
    }
}

/// The C and ARM EABI symbols (`__aeabi_memset` takes the length before the value).
#[cfg(target_os = "none")]
mod symbols {
    use super::{copy, fill};

    macro_rules! copies {
        ($($name:ident),*) => {$(
            /// # Safety
            /// As [`copy`].
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn $name(dest: *mut u8, src: *const u8, n: usize) {
                unsafe { copy(dest, src, n) }
            }
        )*};
    }
    copies!(
        __aeabi_memcpy,
        __aeabi_memcpy4,
        __aeabi_memcpy8,
        __aeabi_memmove,
        __aeabi_memmove4,
        __aeabi_memmove8
    );

    macro_rules! fills {
        ($($name:ident),*) => {$(
            /// # Safety
            /// As [`fill`].
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn $name(dest: *mut u8, n: usize, value: i32) {
                unsafe { fill(dest, value as u8, n) }
            }
        )*};
    }
    fills!(__aeabi_memset, __aeabi_memset4, __aeabi_memset8);

    macro_rules! clears {
        ($($name:ident),*) => {$(
            /// # Safety
            /// As [`fill`].
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn $name(dest: *mut u8, n: usize) {
                unsafe { fill(dest, 0, n) }
            }
        )*};
    }
    clears!(__aeabi_memclr, __aeabi_memclr4, __aeabi_memclr8);

    /// # Safety
    /// As [`copy`].
    #[unsafe(no_mangle)]
    pub unsafe extern "C" fn memcpy(dest: *mut u8, src: *const u8, n: usize) -> *mut u8 {
        unsafe { copy(dest, src, n) };
        dest
    }

    /// # Safety
    /// As [`copy`].
    #[unsafe(no_mangle)]
    pub unsafe extern "C" fn memmove(dest: *mut u8, src: *const u8, n: usize) -> *mut u8 {
        unsafe { copy(dest, src, n) };
        dest
    }

    /// # Safety
    /// As [`fill`].
    #[unsafe(no_mangle)]
    pub unsafe extern "C" fn memset(dest: *mut u8, value: i32, n: usize) -> *mut u8 {
        unsafe { fill(dest, value as u8, n) };
        dest
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use std::vec::Vec;

    /// A buffer of distinct bytes.
    fn pattern(len: usize) -> Vec<u8> {
        (0..len).map(|i| (i * 7 + 3) as u8).collect()
    }

    #[test]
    fn copies_every_length_and_alignment() {
        for n in 0..48 {
            for d in 0..4 {
                for s in 0..4 {
                    let src = pattern(n + 8);
                    let mut dest = std::vec![0xAAu8; n + 8];
                    unsafe { copy(dest.as_mut_ptr().add(d), src.as_ptr().add(s), n) };
                    let mut want = std::vec![0xAAu8; n + 8];
                    want[d..d + n].copy_from_slice(&src[s..s + n]);
                    assert_eq!(dest, want, "n {n} dest +{d} src +{s}");
                }
            }
        }
    }

    #[test]
    fn overlapping_copies_move_as_memmove_does() {
        for n in 0..40 {
            for from in 0..8 {
                for to in 0..8 {
                    let mut buf = pattern(n + 8);
                    let mut want = buf.clone();
                    want.copy_within(from..from + n, to);
                    let p = buf.as_mut_ptr();
                    unsafe { copy(p.add(to), p.add(from), n) };
                    assert_eq!(buf, want, "n {n} from {from} to {to}");
                }
            }
        }
    }

    #[test]
    fn fills_every_length_and_alignment() {
        for n in 0..48 {
            for d in 0..4 {
                for byte in [0u8, 0x5A, 0xFF] {
                    let mut dest = pattern(n + 8);
                    let mut want = dest.clone();
                    want[d..d + n].fill(byte);
                    unsafe { fill(dest.as_mut_ptr().add(d), byte, n) };
                    assert_eq!(dest, want, "n {n} dest +{d} byte {byte}");
                }
            }
        }
    }
}

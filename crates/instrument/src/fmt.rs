//! Logging that goes to defmt on the MCU and to `log` on the host. Use `{}` for numbers and
//! strings and `{:?}` for the crate's types: both back ends read those the same way.
#![allow(unused_macros)]

macro_rules! log_to {
    ($level:ident, $s:literal $(, $x:expr)* $(,)?) => {{
        #[cfg(feature = "defmt")]
        defmt::$level!($s $(, $x)*);
        #[cfg(feature = "log")]
        log::$level!($s $(, $x)*);
        #[cfg(not(any(feature = "defmt", feature = "log")))]
        let _ = ($(&$x),*);
    }};
}

macro_rules! info {
    ($($t:tt)*) => { log_to!(info, $($t)*) };
}

macro_rules! warn {
    ($($t:tt)*) => { log_to!(warn, $($t)*) };
}

macro_rules! error {
    ($($t:tt)*) => { log_to!(error, $($t)*) };
}

macro_rules! debug {
    ($($t:tt)*) => { log_to!(debug, $($t)*) };
}

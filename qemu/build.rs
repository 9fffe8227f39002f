//! The emulated board's memory layout: `memory.x` on the linker's search path, and an empty
//! `defmt.x` for the `-Tdefmt.x` that the repository's cargo config passes (this binary prints
//! through semihosting, not defmt).

fn main() {
    let out = std::path::PathBuf::from(std::env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    std::fs::copy("memory.x", out.join("memory.x")).expect("memory.x beside Cargo.toml");
    std::fs::write(out.join("defmt.x"), "").expect("OUT_DIR is writable");
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rerun-if-changed=memory.x");
}

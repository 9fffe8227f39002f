//! The `nf` host tool (see `crates/nf`), built at `target/release/nf` by `cargo build --release`.

fn main() -> std::process::ExitCode {
    nf::main()
}

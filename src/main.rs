//! The `strider` binary: everything lives in the library's [`strider::cli`].

fn main() -> std::process::ExitCode {
    strider::cli::main()
}

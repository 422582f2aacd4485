//! `hj`: the hamilton-jacobi command line on the built-in catalogue (see
//! [`hamilton_jacobi::cli`] for the subcommands and for a command line of your own systems).

use hamilton_jacobi::scene::Catalogue;
use std::process::ExitCode;

fn main() -> ExitCode {
    hamilton_jacobi::cli::cli_main(Catalogue::builtin())
}

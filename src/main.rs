//! The `wmslice` command line: the edge of the program, where typed library
//! errors become messages and documented exit codes.

mod cli;

fn main() {
    std::process::exit(cli::run());
}

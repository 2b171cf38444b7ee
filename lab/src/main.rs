//! `rcg-lab`: the laboratory's runners as subcommands (`diku`, `disturb`, `stability`,
//! `frames`); see [`rcg_lab::cli`]. Run with `cargo lab SUBCOMMAND [OPTIONS]`.

fn main() -> std::process::ExitCode {
    rcg_lab::cli::main()
}

//! `scatterlab`: parse the command line, then run a subcommand.

use clap::Parser;
use std::process::ExitCode;

/// mimalloc, not the system allocator: glibc's malloc keeps what each
/// worker thread (render, analysis, the ground truth's pool) frees in that
/// thread's arena, and the editor's resident memory grew 50 % over a
/// 21-minute soak that way (`MALLOC_ARENA_MAX=2` held it flat); mimalloc
/// gives freed pages back (docs/robustness.md has the figures). Its v2
/// line (Cargo.toml): v3 holds freed pages for a second, and the ground
/// truth's peak went over its 400 MB budget with it.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() -> ExitCode {
    // Mesa's Vulkan WSI probes Wayland and prints "XDG_RUNTIME_DIR is invalid"
    // on headless machines; give it a private directory so a successful
    // render prints no error lines.
    if std::env::var_os("XDG_RUNTIME_DIR").is_none() {
        let dir = std::env::temp_dir().join("scatterlab-runtime");
        if std::fs::create_dir_all(&dir).is_ok() {
            std::env::set_var("XDG_RUNTIME_DIR", &dir);
        }
    }
    let cli = match scatterlab::cli::Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            use clap::error::ErrorKind;
            if matches!(
                e.kind(),
                ErrorKind::DisplayHelp
                    | ErrorKind::DisplayVersion
                    | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand
            ) {
                let _ = e.print();
                return ExitCode::SUCCESS;
            }
            // One line: clap's first line names the problem.
            let text = e.to_string();
            eprintln!(
                "{}",
                text.lines().next().unwrap_or("error: invalid arguments")
            );
            return ExitCode::from(2);
        }
    };
    match scatterlab::cli::run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            let chain: Vec<String> = e.chain().map(|c| c.to_string()).collect();
            eprintln!("error: {}", chain.join(": ").replace('\n', " "));
            ExitCode::FAILURE
        }
    }
}

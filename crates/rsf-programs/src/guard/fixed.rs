//! The guard of a program of fixed size: [`fixed_size_program!`](crate::fixed_size_program).

/// The `main` of a program whose size no flag changes (a tutorial example): the flags every
/// program takes (`--max-memory-gb`, `--max-output-gb`, `--help`, `--version`), its name,
/// the memory it needs (bytes, an upper bound) and what it computes; `run` is a function
/// `fn() -> Result<(), E>` with `E` any error (printed with its causes, exit code 1).
/// The program writes no file (nothing but the terminal's lines). Expands to a `Cli`
/// struct (clap derive: the caller's crate depends on `clap`), its
/// [`Program`](crate::guard::Program) implementation and `fn main`.
///
/// ```no_run
/// fn run() -> Result<(), std::io::Error> {
///     println!("a fixed problem");
///     Ok(())
/// }
///
/// rsf_programs::fixed_size_program! {
///     name: "heterogeneous_fault",
///     memory_bytes: 2e8,
///     what: "an 8 m × 1 m block at level 3 (585 nodes)",
///     run: run,
/// }
/// ```
#[macro_export]
macro_rules! fixed_size_program {
    (name: $name:literal, memory_bytes: $bytes:expr, what: $what:literal, run: $run:path $(,)?) => {
        /// The program's flags: only the bounds every program takes (no input changes its
        /// size).
        #[derive(clap::Parser)]
        #[command(version)]
        struct Cli {
            #[command(flatten)]
            limits: $crate::guard::Limits,
        }

        impl $crate::guard::Program for Cli {
            $crate::name_and_limits!($name);

            fn plan(&self) -> Result<$crate::guard::Plan, $crate::guard::AnyError> {
                Ok($crate::guard::Plan::new().memory($bytes, "(none)", $what))
            }
        }

        // `Ok(run()?)` converts any error type into the guard's (needless only for `run`s
        // that already return the boxed error).
        #[allow(clippy::needless_question_mark)]
        fn main() -> std::process::ExitCode {
            // --help; rejects unknown flags; errors printed with their causes, exit code 1.
            $crate::guard::main(|_: Cli, _| Ok($run()?))
        }
    };
}

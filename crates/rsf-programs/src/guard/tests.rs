use super::{agree_on_flags, parse_from, Limits, Plan, Program};

/// A program for the tests: two valued flags and a switch.
#[derive(clap::Parser)]
struct Toy {
    #[arg(long, default_value_t = 1800.0)]
    end_years: f64,
    #[arg(long, default_value_t = 2000.0)]
    dx: f64,
    #[arg(long)]
    overwrite: bool,
}

impl Program for Toy {
    const NAME: &'static str = "toy";
    fn limits(&self) -> Limits {
        Limits::default()
    }
    fn plan(&self) -> Result<Plan, super::AnyError> {
        Ok(Plan::new())
    }
}

fn flags(args: &[&str]) -> String {
    let args = std::iter::once("toy").chain(args.iter().copied());
    parse_from::<Toy, _, _>(args).unwrap().1
}

/// The flags as given, whatever their spelling; the defaults are not listed.
#[test]
fn the_given_flags_are_those_of_the_command_line_as_read() {
    assert_eq!(flags(&[]), "the program `toy`");
    assert_eq!(
        flags(&["--end-years", "5", "--overwrite"]),
        flags(&["--overwrite", "--end-years=5"])
    );
    assert_eq!(
        flags(&["--end-years", "5", "--overwrite"]),
        "the program `toy`\n--end-years 5\n--overwrite"
    );
    assert_ne!(flags(&["--dx", "-1"]), flags(&["--dx", "1"]));
}

/// Each rank's verdict on the flags `given[rank]`, computed on a thread per rank.
fn verdicts(given: &[String]) -> Vec<Result<(), String>> {
    std::thread::scope(|s| {
        let handles: Vec<_> = given
            .iter()
            .zip(rsf_ranks::ThreadRanks::group(given.len()))
            .map(|(flags, mut group)| s.spawn(move || agree_on_flags(&mut group, flags)))
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    })
}

/// Ranks started with the same flags agree; with different ones every rank gets the
/// same error, naming the rank and the flag on both sides (issue 74: an MPMD launch
/// with another `--end-years` on one rank hung, another `--dx` crashed).
#[test]
fn ranks_with_different_flags_end_every_one_with_the_same_named_error() {
    let same = vec![flags(&["--end-years", "5"]); 3];
    assert!(verdicts(&same).iter().all(Result::is_ok));
    let mut given = same.clone();
    given[2] = flags(&["--end-years", "50"]);
    let v = verdicts(&given);
    let e = v[0].clone().unwrap_err();
    assert!(v.iter().all(|r| r.as_ref().err() == Some(&e)), "{v:?}");
    assert!(
        e.contains("rank 2 has `--end-years 50` where rank 0 has `--end-years 5`"),
        "{e}"
    );
    // A flag given on one rank only, and another program.
    given[1] = flags(&["--end-years", "5", "--dx", "1000"]);
    let e = verdicts(&given)[1].clone().unwrap_err();
    assert!(e.contains("ranks 1, 2 of 3"), "{e}");
    assert!(
        e.contains("rank 1 has `--dx 1000` where rank 0 has nothing else"),
        "{e}"
    );
    let other = vec![same[0].clone(), same[0].replace("`toy`", "`seas_bp3`")];
    let e = verdicts(&other)[0].clone().unwrap_err();
    assert!(e.contains("the program `seas_bp3`"), "{e}");
}

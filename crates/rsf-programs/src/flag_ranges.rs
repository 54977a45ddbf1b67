//! Every numeric flag's range as `--help` states it is the range its check applies (issue
//! 87, "Flags that do what they say"): for each program, the test reads every flag's help
//! from the program's clap command (in process), takes the range it states (`in [lo, hi]`,
//! `(lo, hi]`, …), and plans the program (nothing built or run) with the flag just inside
//! and just outside each bound — the bound itself and the next `f64` beyond it — asserting
//! the value inside admitted and the value outside refused, naming the flag and showing
//! the value as written. A numeric flag that states no range is listed in the test with
//! the reason. A range that is a constant is written once, in [`flag_range!`], which
//! gives both the help text and the check's bounds.
//!
//! [`flag_range!`]: crate::guard::flag_range

#[cfg(test)]
mod tests {
    use crate::guard::{parse_from, written, Program};

    /// A range a flag's help states: the bounds and whether each is included.
    #[derive(Debug, Clone, Copy, PartialEq)]
    struct Stated {
        lo: f64,
        hi: f64,
        lo_closed: bool,
        hi_closed: bool,
    }

    /// The first range stated in `help`: `in [lo, hi]`, `in (lo, hi]`, `in [lo, hi)` or
    /// `in (lo, hi)` (numbers as Rust parses them, `inf` included).
    fn stated(help: &str) -> Option<Stated> {
        let mut rest = help;
        while let Some(i) = rest.find("in ") {
            let after = &rest[i + 3..];
            let open = after.chars().next();
            if let Some(open @ ('[' | '(')) = open {
                let close = after.find([']', ')'])?;
                let inner = &after[1..close];
                let (lo, hi) = inner.split_once(',')?;
                let (lo, hi) = (lo.trim().parse().ok()?, hi.trim().parse().ok()?);
                return Some(Stated {
                    lo,
                    hi,
                    lo_closed: open == '[',
                    hi_closed: after[close..].starts_with(']'),
                });
            }
            rest = after;
        }
        None
    }

    /// Probes planned by [`check`] (the test asserts it probed the flags it names).
    static PROBES: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);

    /// The next `f64` above and below `x`.
    fn up(x: f64) -> f64 {
        x.next_up()
    }
    fn down(x: f64) -> f64 {
        x.next_down()
    }

    /// Whether clap reads `arg` as a number.
    fn numeric(arg: &clap::Arg) -> bool {
        let id = arg.get_value_parser().type_id();
        let of = |a: clap::Arg| a.get_value_parser().type_id();
        [
            of(clap::Arg::new("x").value_parser(clap::value_parser!(f64))),
            of(clap::Arg::new("x").value_parser(clap::value_parser!(usize))),
            of(clap::Arg::new("x").value_parser(clap::value_parser!(u64))),
            of(clap::Arg::new("x").value_parser(clap::value_parser!(u32))),
        ]
        .contains(&id)
    }

    /// The program `P` planned with `flags` (after `base`): `Ok` if admitted, the refusal's
    /// message if not (a flag clap refuses counts as refused).
    fn plan<P: Program>(base: &[&str], flags: &[String]) -> Result<(), String> {
        let args = std::iter::once(P::NAME.to_owned())
            .chain(base.iter().map(|s| (*s).to_owned()))
            .chain(flags.iter().cloned());
        let (program, _) = parse_from::<P, _, _>(args).map_err(|e| e.to_string())?;
        program.plan().map(|_| ()).map_err(|e| e.to_string())
    }

    /// Checks every numeric flag of `P`: its stated range against its check (with `base`
    /// before the flags, and `extra` the flags a flag needs to be used, e.g. `--kernel fe`),
    /// or its listing in `none` (flags that state no range, each with its reason).
    /// Returns the disagreements found.
    fn check<P: Program>(
        base: &[&str],
        extra: &[(&str, &[&str])],
        none: &[(&str, &str)],
    ) -> Vec<String> {
        let mut wrong = Vec::new();
        let command = P::command();
        for arg in command.get_arguments() {
            let Some(long) = arg.get_long() else { continue };
            if !numeric(arg) {
                continue;
            }
            let flag = format!("--{long}");
            let help = arg
                .get_long_help()
                .or(arg.get_help())
                .map(ToString::to_string)
                .unwrap_or_default();
            let Some(range) = stated(&help) else {
                if !none.iter().any(|(f, _)| *f == flag) {
                    wrong.push(format!(
                        "{} {flag}: a numeric flag whose help states no range and which the \
                         test does not list (help: {help:?})",
                        P::NAME
                    ));
                }
                continue;
            };
            let needs: Vec<String> = extra
                .iter()
                .filter(|(f, _)| *f == flag)
                .flat_map(|(_, e)| e.iter().map(|s| (*s).to_owned()))
                .collect();
            let mut probes = Vec::new();
            // A whole-number flag's neighbours are the next whole numbers.
            let real = arg.get_value_parser().type_id()
                == clap::Arg::new("x")
                    .value_parser(clap::value_parser!(f64))
                    .get_value_parser()
                    .type_id();
            let (up, down) = if real {
                (up as fn(f64) -> f64, down as fn(f64) -> f64)
            } else {
                (
                    (|x| x + 1.0) as fn(f64) -> f64,
                    (|x| x - 1.0) as fn(f64) -> f64,
                )
            };
            let (lo_in, lo_out) = if range.lo_closed {
                (range.lo, down(range.lo))
            } else {
                (up(range.lo), range.lo)
            };
            let (hi_in, hi_out) = if range.hi_closed {
                (range.hi, up(range.hi))
            } else {
                (down(range.hi), range.hi)
            };
            for (value, inside) in [
                (lo_in, true),
                (lo_out, false),
                (hi_in, true),
                (hi_out, false),
            ] {
                // An integer flag's bounds are probed at the integers next to them; an
                // infinite bound has nothing beyond it.
                if value.is_infinite() && !inside {
                    continue;
                }
                probes.push((value, inside));
            }
            for (value, inside) in probes {
                let text = if real {
                    written(value)
                } else if value.fract() == 0.0 && value >= 0.0 {
                    format!("{value:.0}")
                } else {
                    continue;
                };
                // `--flag=value`: a negative value is the flag's, not another flag.
                let mut flags = needs.clone();
                flags.push(format!("{flag}={text}"));
                PROBES.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                match (plan::<P>(base, &flags), inside) {
                    (Ok(()), true) => {}
                    // A size limit inside its range refusing an estimate above it is the
                    // limit at work (the slider plans its output against it), not its range.
                    (Err(e), true) if e.contains("estimated") && e.contains(&flag) => {}
                    (Err(e), false) if e.contains(&flag) && e.contains(&text) => {}
                    (Err(e), false) if e.contains(&flag) => wrong.push(format!(
                        "{} {flag} {text}: refused without the value as written: {e}",
                        P::NAME
                    )),
                    (Ok(()), false) => wrong.push(format!(
                        "{} {flag} {text}: admitted, outside the stated {help:?}",
                        P::NAME
                    )),
                    (Err(e), _) => wrong.push(format!(
                        "{} {flag} {text} ({}): {e} (the help states {help:?})",
                        P::NAME,
                        if inside { "inside" } else { "outside" }
                    )),
                }
            }
        }
        wrong
    }

    #[test]
    fn the_parser_reads_stated_ranges() {
        let s = stated("End time (years), in [1e-9, 100].").unwrap();
        assert_eq!(
            (s.lo, s.hi, s.lo_closed, s.hi_closed),
            (1e-9, 100.0, true, true)
        );
        let s = stated("in (0, inf] GB").unwrap();
        assert_eq!(
            (s.lo, s.hi, s.lo_closed, s.hi_closed),
            (0.0, f64::INFINITY, false, true)
        );
        assert_eq!(stated("Output folder (in the run's [files])."), None);
    }

    /// Flags every program shares (`crate::guard::Limits`, `crate::ResumeArgs`, …) that
    /// state no range, and why.
    const SHARED_NONE: &[(&str, &str)] = &[
        (
            "--threads",
            "checked against the machine (`check_threads`: at least 1, at most what it can \
             start), not a constant range",
        ),
        ("--max-steps", "any count; 0 computes no step"),
        ("--checkpoint-every", "any count; 0: never"),
        (
            "--hdf5",
            "any count; 0: no fields file (without crates/rsf-hdf5's writers any other is \
             refused, NoFieldWriter)",
        ),
    ];

    fn report(wrong: Vec<String>) {
        assert!(
            wrong.is_empty(),
            "{} disagreements:\n{}",
            wrong.len(),
            wrong.join("\n")
        );
    }

    #[cfg(feature = "seas")]
    #[test]
    fn every_numeric_flags_help_range_is_its_checks_range() {
        let mut wrong = Vec::new();
        wrong.extend(check::<crate::seas_bp6::Args>(
            &[],
            &[
                ("--diffusion-cells", &["--pressure", "diffusion"]),
                ("--kernel-epsilon", &["--bem-product", "stored"]),
            ],
            SHARED_NONE,
        ));
        // The finite-element box's flags need `--kernel fe`; with `--max-memory-gb` far
        // below any estimate the plan stops at its bound before the box is meshed.
        let square_fe: &[&str] = &["--kernel", "fe", "--max-memory-gb", "1e-6"];
        let square_box: &[(&str, &[&str])] = &[("--domain-km", square_fe), ("--ratio", square_fe)];
        wrong.extend(check::<crate::seas_bp7::Args>(&[], square_box, SHARED_NONE));
        let implicit: &[&str] = &["--scheme", "implicit"];
        let inertia: &[&str] = &["--inertia"];
        wrong.extend(check::<crate::seas_bp1::Args>(
            &["--out", "out/seas_bp1"],
            &[
                ("--tolerance", implicit),
                ("--state-change-cap", implicit),
                ("--fixed-point-tolerance", implicit),
                ("--switch-to-dynamic", inertia),
                ("--switch-to-quasi-dynamic", inertia),
                ("--dynamic-fixed-point-tolerance", inertia),
            ],
            &[
                SHARED_NONE,
                &[
                    (
                        "--dz",
                        "must divide W_f = 40 km into whole cells; the model's size is bounded \
                         by --max-memory-gb",
                    ),
                    (
                        "--domain-km",
                        "must exceed W_f = 40 km; the model's size is bounded by \
                         --max-memory-gb",
                    ),
                    (
                        "--dynamic-tau",
                        "a range of the element's crossing time Δz/c_s, [1e-3, 1] of it, \
                         stated in the refusal (it depends on --dz)",
                    ),
                    (
                        "--w-f",
                        "a whole number of --dz cells, less than the domain (--domain-km): \
                         its range depends on both, stated in the refusal",
                    ),
                ],
            ]
            .concat(),
        ));
        wrong.extend(check::<crate::seas_bp8::Args>(&[], square_box, SHARED_NONE));
        let dx_fits: &[&str] = &[
            "--gap-km",
            "3.75",
            "--overlap-km",
            "3.75",
            "--strand-km",
            "18.75",
        ];
        wrong.extend(check::<crate::stepover::Args>(
            &[],
            // The largest --dx, 1875 m, divides half of this gap and overlap and the
            // strand's frictional length.
            &[
                ("--dx", dx_fits),
                // The narrowest gap, 2 m, is two cells of the smallest --dx.
                ("--gap-km", &["--dx", "1"]),
                // The shortest strand overlaps nothing; the longest needs a box as long.
                ("--strand-km", &["--overlap-km", "0", "--domain-km", "1e4"]),
            ],
            &[
                SHARED_NONE,
                &[
                    (
                        "--overlap-km",
                        "within ±0.9 --strand-km, stated so in the help",
                    ),
                    (
                        "--domain-km",
                        "from --strand-km to 1e5, stated so in the help",
                    ),
                ],
            ]
            .concat(),
        ));
        wrong.extend(check::<crate::seas_bp3::Args>(&[], &[], SHARED_NONE));
        wrong.extend(check::<crate::bp5_pair::Args>(&[], &[], SHARED_NONE));
        // The finite-element flags need `--kernel fe`; the tensor grid's size is
        // arithmetic (the graded mesh would be built), and with `--max-memory-gb` far
        // below any estimate the graded plan stops at its bound, unmeshed.
        let fe_tensor: &[&str] = &["--kernel", "fe", "--mesh", "tensor"];
        let zone: &[&str] = &[
            "--kernel",
            "fe",
            "--fault-zone-width-km",
            "4",
            "--max-memory-gb",
            "1e-6",
        ];
        wrong.extend(check::<crate::seas_bp5::Args>(
            &[],
            &[
                ("--domain-km", fe_tensor),
                ("--ratio", fe_tensor),
                ("--fault-zone-rigidity", zone),
            ],
            &[
                SHARED_NONE,
                &[
                    (
                        "--dx",
                        "must divide l_f = 100 km and W_f = 40 km into whole cells; the \
                         model's size is bounded by --max-memory-gb",
                    ),
                    (
                        "--fault-zone-width-km",
                        "a whole number of 2 --dx, stated so in the help",
                    ),
                ],
            ]
            .concat(),
        ));
        let slider_none: &[(&str, &str)] = &[
            (
                "--steps",
                "a positive whole number of steps (`step_count`); the run's files bounded by \
                 --max-output-gb",
            ),
            ("--frame-every", "any count; 0: no frames"),
            (
                "--end-time-s",
                "positive and at most 1e10 s, stated so in the help; its least value depends on \
                 --steps (the step T/N must give finite coefficients: 2.2e-308 s is refused \
                 naming steps)",
            ),
            (
                "--fixed-point-max-iterations",
                "any count from 1, stated so in the help",
            ),
        ];
        wrong.extend(check::<crate::pipping_slider::Cli>(
            &[],
            &[("--adaptive", &["--steps", "1000"])],
            &[SHARED_NONE, slider_none].concat(),
        ));
        wrong.extend(check::<crate::slider_3d::Cli>(
            &[],
            &[],
            &[
                SHARED_NONE,
                slider_none,
                &[(
                    "--snapshot-time",
                    "inside [0, T], T the run's end time (--end-time or the scene's), stated in \
                     the refusal",
                )],
            ]
            .concat(),
        ));
        wrong.extend(check::<crate::distributed_sweep::Args>(
            &[],
            &[],
            &[
                SHARED_NONE,
                &[
                    (
                        "--refinements",
                        "any count: bounded by the memory estimate (--max-memory-gb), which \
                         states it",
                    ),
                    (
                        "--levels",
                        "in [1, R + 1], R the --refinements, stated in the refusal",
                    ),
                    (
                        "--thread-ranks",
                        "a thread count, checked against the machine as --threads",
                    ),
                ],
            ]
            .concat(),
        ));
        let probes = PROBES.load(std::sync::atomic::Ordering::Relaxed);
        eprintln!("{probes} values planned at the stated bounds");
        assert!(probes >= 150, "only {probes} probes");
        report(wrong);
    }

    /// The program `P` with `flags` planned and its plan checked against its limits: the
    /// refusal's message (`None`: admitted).
    fn refusal<P: Program>(flags: &[&str]) -> Option<String> {
        let args = std::iter::once(P::NAME).chain(flags.iter().copied());
        let (program, _) = match parse_from::<P, _, _>(args) {
            Ok(p) => p,
            Err(e) => return Some(e.to_string()),
        };
        match program.plan() {
            Ok(plan) => plan.check(program.limits()).err().map(|e| e.to_string()),
            Err(e) => Some(e.to_string()),
        }
    }

    /// A refused value is shown as the user wrote it (issue 87): never ~300 digits
    /// (`1e-300`), never rounded so that it reads as the bound it exceeds (`2000.0000001`
    /// was shown as `2.000e3`); and the refusal names the flag that set it (the
    /// finite-element grid's refusals blamed `--dx` for the fault zone's width).
    #[cfg(feature = "seas")]
    #[test]
    fn refusals_show_values_as_written() {
        type Case = (
            &'static str,
            fn(&[&str]) -> Option<String>,
            &'static [&'static str],
            &'static str,
            &'static str,
        );
        let cases: &[Case] = &[
            (
                "seas_bp1",
                refusal::<crate::seas_bp1::Args>,
                &[
                    "--out",
                    "o",
                    "--scheme",
                    "implicit",
                    "--tolerance",
                    "1e-300",
                ],
                "--tolerance",
                "1e-300",
            ),
            (
                "seas_bp1",
                refusal::<crate::seas_bp1::Args>,
                &["--out", "o", "--rk-tolerance", "1e-300"],
                "--rk-tolerance",
                "1e-300",
            ),
            (
                "seas_bp1",
                refusal::<crate::seas_bp1::Args>,
                &["--out", "o", "--max-memory-gb", "1e-300"],
                "--max-memory-gb",
                "1e-300",
            ),
            (
                "seas_bp1",
                refusal::<crate::seas_bp1::Args>,
                &["--out", "o", "--dz", "25.0000001"],
                "--dz",
                "25.0000001",
            ),
            (
                "seas_bp3",
                refusal::<crate::seas_bp3::Args>,
                &["--dx", "1e-300"],
                "--dx",
                "1e-300",
            ),
            (
                "seas_bp3",
                refusal::<crate::seas_bp3::Args>,
                &["--max-output-gb", "1e-300"],
                "--max-output-gb",
                "1e-300",
            ),
            (
                "seas_bp5",
                refusal::<crate::seas_bp5::Args>,
                &["--dx", "2000.0000001"],
                "--dx",
                "2000.0000001",
            ),
            (
                "seas_bp5",
                refusal::<crate::seas_bp5::Args>,
                &["--tolerance", "1e-300"],
                "--tolerance",
                "1e-300",
            ),
            (
                "seas_bp5",
                refusal::<crate::seas_bp5::Args>,
                &[
                    "--kernel",
                    "fe",
                    "--fault-zone-width-km",
                    "10",
                    "--fault-zone-rigidity",
                    "0.5",
                ],
                "--fault-zone-width-km",
                "5e3",
            ),
            (
                "seas_bp5",
                refusal::<crate::seas_bp5::Args>,
                &[
                    "--kernel",
                    "fe",
                    "--fault-zone-width-km",
                    "4",
                    "--fault-zone-rigidity",
                    "1.0000001",
                ],
                "--fault-zone-rigidity",
                "1.0000001",
            ),
            (
                "seas_bp6",
                refusal::<crate::seas_bp6::Args>,
                &["--dz", "10.0000001"],
                "--dz",
                "10.0000001",
            ),
            (
                "seas_bp6",
                refusal::<crate::seas_bp6::Args>,
                &["--dz", "10000.0000001"],
                "--dz",
                "10000.0000001",
            ),
            (
                "seas_bp7",
                refusal::<crate::seas_bp7::Args>,
                &["--dx", "10.0000001"],
                "--dx",
                "10.0000001",
            ),
            (
                "seas_bp8",
                refusal::<crate::seas_bp8::Args>,
                &["--dx", "10.0000001"],
                "--dx",
                "10.0000001",
            ),
            (
                "seas_bp8",
                refusal::<crate::seas_bp8::Args>,
                &["--sigma-min", "12.5000001"],
                "--sigma-min",
                "12.5000001",
            ),
            (
                "stepover",
                refusal::<crate::stepover::Args>,
                &["--dx", "25.0000001"],
                "--dx",
                "25.0000001",
            ),
            (
                "bp5_pair",
                refusal::<crate::bp5_pair::Args>,
                &["--dx", "2000.0000001"],
                "--dx",
                "2000.0000001",
            ),
            (
                "bp5_pair",
                refusal::<crate::bp5_pair::Args>,
                &["--kernel", "fe", "--separation-km", "8.0000001"],
                "--separation-km",
                "8.0000001",
            ),
        ];
        let mut wrong = Vec::new();
        for (name, refused, flags, flag, shown) in cases {
            match refused(flags) {
                // Named by its flag, never blaming --dx for another flag's value.
                Some(e)
                    if e.contains(flag)
                        && e.contains(shown)
                        && (*flag == "--dx" || !e.starts_with("--dx")) => {}
                Some(e) => wrong.push(format!("{name} {flags:?}: `{shown}` by {flag}: {e}")),
                None => wrong.push(format!("{name} {flags:?}: admitted")),
            }
        }
        report(wrong);
    }

    /// The ℋ-matrices' relative accuracy: `bp5_pair --epsilon`'s stated range is the library's
    /// (`rsf::fault_ode::MIN_KERNEL_EPSILON`, `MAX_KERNEL_EPSILON`), which every kernel checks.
    #[test]
    fn the_pairs_epsilon_range_is_the_librarys() {
        assert_eq!(
            crate::bp5_pair::EPSILON,
            (
                rsf::fault_ode::MIN_KERNEL_EPSILON,
                rsf::fault_ode::MAX_KERNEL_EPSILON
            )
        );
    }
}

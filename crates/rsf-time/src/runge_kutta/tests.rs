use super::*;

/// `y' = λ y` (or a 2-D rotation), tolerance-scaled error = max |err| / tol.
struct Linear {
    tol: f64,
}

impl OdeSystem for Linear {
    type Error = Error;
    fn rate(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<()> {
        dy[0] = -y[1];
        dy[1] = y[0];
        Ok(())
    }
    fn scaled_error(&self, _y: &[f64], _y_new: &[f64], err: &[f64]) -> f64 {
        err.iter().fold(0.0_f64, |m, e| m.max(e.abs())) / self.tol
    }
}

/// The stage and error combinations, one pass per coefficient, have the bits of the
/// scalar sums over the coefficients entry by entry (in the order of `l`, from 0.0,
/// skipping zeros) — signed zeros, subnormals and cancellation included — for every
/// row of both tableaux.
#[test]
fn combinations_have_the_bits_of_the_entrywise_sums() {
    let n = 37;
    let k: Vec<Vec<f64>> = (0..7)
        .map(|l| {
            (0..n)
                .map(|j| match (j + l) % 6 {
                    0 => -0.0,
                    1 => 0.0,
                    2 => 5e-324 * (l as f64 + 1.0),
                    3 => 1e16 * ((j * 7 + l) as f64).sin(),
                    _ => ((j * 13 + l * 5) as f64 * 0.61).cos(),
                })
                .collect()
        })
        .collect();
    let mut out = vec![f64::NAN; n];
    for tab in [DORMAND_PRINCE_54, BOGACKI_SHAMPINE_32] {
        for c in tab.a.iter().copied().chain([tab.e]) {
            combine(&mut out, c, &k);
            for (j, o) in out.iter().enumerate() {
                let mut acc = 0.0;
                for (l, &cl) in c.iter().enumerate() {
                    if cl != 0.0 {
                        acc += cl * k[l][j];
                    }
                }
                assert_eq!(o.to_bits(), acc.to_bits(), "{} entry {j}", tab.name);
            }
        }
    }
}

fn run(tab: Tableau, tol: f64) -> (f64, usize) {
    let mut rk = EmbeddedRungeKutta::new(tab, RungeKuttaOptions::default(), 2, 1e-3).unwrap();
    let (mut t, mut y) = (0.0, [1.0, 0.0]);
    let mut sys = Linear { tol };
    let mut steps = 0;
    while t < 10.0 {
        rk.step(&mut sys, &mut t, &mut y, Some(10.0)).unwrap();
        steps += 1;
    }
    assert_eq!(t, 10.0);
    let e = (y[0] - 10f64.cos()).abs().max((y[1] - 10f64.sin()).abs());
    (e, steps)
}

/// The global error of the rotation over 10 s falls with the tolerance at the rate of
/// the pair's order: steps ∝ tol^(−1/(q+1)), error ∝ steps^(−p) — measured through
/// error ∝ tol^(p/(q+1)) over two decades.
#[test]
fn global_error_follows_the_order_of_each_pair() {
    for (tab, p) in [(DORMAND_PRINCE_54, 5.0), (BOGACKI_SHAMPINE_32, 3.0)] {
        let (e1, n1) = run(tab, 1e-6);
        let (e2, n2) = run(tab, 1e-8);
        let order = (e1 / e2).ln() / (n2 as f64 / n1 as f64).ln();
        println!(
            "{}: errors {e1:e} ({n1} steps), {e2:e} ({n2} steps), order {order:.2}",
            tab.name
        );
        assert!(
            (order - p).abs() < 0.6,
            "{}: observed order {order}",
            tab.name
        );
    }
}

/// The tableaux are consistent: rows sum to c, b sums to 1, the embedded weights too.
#[test]
fn tableaux_are_consistent() {
    for tab in [DORMAND_PRINCE_54, BOGACKI_SHAMPINE_32] {
        for (i, row) in tab.a.iter().enumerate() {
            let s: f64 = row.iter().sum();
            assert!(
                (s - tab.c[i + 1]).abs() < 1e-14,
                "{} row {}",
                tab.name,
                i + 1
            );
        }
        let b = tab.a[tab.stages - 2];
        assert!((b.iter().sum::<f64>() - 1.0).abs() < 1e-14);
        assert!(tab.e.iter().sum::<f64>().abs() < 1e-14);
    }
}

/// `y' = 1` that blows up (a NaN rate) beyond `y = 1.5`, at a tolerance of 1e-9.
struct Blow;

impl OdeSystem for Blow {
    type Error = Error;
    fn rate(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<()> {
        dy[0] = if y[0] > 1.5 { f64::NAN } else { 1.0 };
        Ok(())
    }
    fn scaled_error(&self, _y: &[f64], _n: &[f64], err: &[f64]) -> f64 {
        err[0].abs() / 1e-9
    }
}

/// A non-finite stage is a rejection, not an error; a step that must fall below
/// `dt_min` is the typed error.
#[test]
fn blow_up_is_rejected_and_a_vanishing_step_is_an_error() {
    let mut rk =
        EmbeddedRungeKutta::new(DORMAND_PRINCE_54, RungeKuttaOptions::default(), 1, 1.0).unwrap();
    let (mut t, mut y) = (0.0, [1.0]);
    let s = rk.step(&mut Blow, &mut t, &mut y, None).unwrap();
    assert!(s.rejected > 0 && s.dt < 0.5 && y[0] <= 1.5, "{s:?}");
    let mut got = Ok(s);
    for _ in 0..1000 {
        got = rk.step(&mut Blow, &mut t, &mut y, None);
        if got.is_err() {
            break;
        }
    }
    assert!(matches!(got, Err(Error::StepTooSmall { .. })), "{got:?}");
}

/// `y' = −y` whose rate refuses trial points with `y < 0` (outside its domain) when
/// `refuse` is set.
struct Decay {
    tol: f64,
    refuse: bool,
}

#[derive(Debug, PartialEq)]
enum DecayError {
    Negative(f64),
    Time(Error),
}

impl From<Error> for DecayError {
    fn from(e: Error) -> Self {
        Self::Time(e)
    }
}

impl std::fmt::Display for DecayError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Negative(y) => write!(f, "y = {y} < 0"),
            Self::Time(e) => write!(f, "{e}"),
        }
    }
}

impl OdeSystem for Decay {
    type Error = DecayError;
    fn rate(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> std::result::Result<(), DecayError> {
        if self.refuse && y[0] < 0.0 {
            return Err(DecayError::Negative(y[0]));
        }
        dy[0] = -y[0];
        Ok(())
    }
    fn scaled_error(&self, y: &[f64], y_new: &[f64], err: &[f64]) -> f64 {
        err[0].abs() / (self.tol * (1e-3 + y[0].abs().max(y_new[0].abs())))
    }
    fn outside_domain(&self, e: &DecayError) -> bool {
        matches!(e, DecayError::Negative(_))
    }
}

/// Integrates `Decay` to `t = 5` from a first step of 10 s (its first stages reach
/// `y < 0`): the answer, the refused and the rejected attempts.
fn decay(refuse: bool) -> (f64, usize, usize) {
    let tol = 1e-8;
    let mut rk =
        EmbeddedRungeKutta::new(DORMAND_PRINCE_54, RungeKuttaOptions::default(), 1, 10.0).unwrap();
    let (mut t, mut y) = (0.0, [1.0]);
    let mut sys = Decay { tol, refuse };
    let (mut refused, mut rejected) = (0, 0);
    while t < 5.0 {
        let s = rk.step(&mut sys, &mut t, &mut y, Some(5.0)).unwrap();
        assert!(s.refused <= s.rejected, "{s:?}");
        refused += s.refused;
        rejected += s.rejected;
    }
    (y[0], refused, rejected)
}

/// A rate function that refuses the overshooting first stages (`y < 0` at a step of
/// 10 s) makes the controller shrink the step and recover: the run completes, counts
/// its refusals among its rejections, and agrees with `e^{−5}` and with the run
/// without refusals (whose error test rejects the same steps) within the tolerance.
#[test]
fn a_refused_stage_shrinks_the_step_and_the_run_recovers() {
    let (with, refused, rejected) = decay(true);
    let (without, none, rejected_without) = decay(false);
    println!(
        "refusing: y(5) = {with:e} ({refused} refused of {rejected} rejected); \
         not: {without:e} ({rejected_without} rejected); exact {:e}",
        (-5.0f64).exp()
    );
    assert!(refused > 0 && rejected >= refused, "{refused} {rejected}");
    assert_eq!(none, 0);
    let exact = (-5.0f64).exp();
    assert!((with - exact).abs() < 1e-6 * exact, "{with} vs {exact}");
    assert!((with - without).abs() < 1e-6 * exact, "{with} vs {without}");
}

/// `y' = 1` whose rate refuses every time beyond `t = 1` as outside its domain.
struct Wall;

impl OdeSystem for Wall {
    type Error = Error;
    fn rate(&mut self, t: f64, _y: &[f64], dy: &mut [f64]) -> Result<()> {
        if t > 1.0 {
            return Err(Error::InvalidParameter {
                name: "t",
                value: t,
                requirement: "at most 1",
            });
        }
        dy[0] = 1.0;
        Ok(())
    }
    fn scaled_error(&self, _y: &[f64], _n: &[f64], err: &[f64]) -> f64 {
        err[0].abs()
    }
    fn outside_domain(&self, e: &Error) -> bool {
        matches!(e, Error::InvalidParameter { name: "t", .. })
    }
}

/// A system that refuses every stage beyond `t = 1` stops with the typed error naming
/// the time, the last step and the reason after `max_refusals` refusals; a refusal at
/// the accepted point (the first evaluation) is the system's own error.
#[test]
fn refusals_are_capped_and_the_accepted_point_is_not_refused() {
    let options = RungeKuttaOptions {
        max_refusals: 3,
        ..RungeKuttaOptions::default()
    };
    let mut rk = EmbeddedRungeKutta::new(DORMAND_PRINCE_54, options, 1, 0.5).unwrap();
    let (mut t, mut y) = (0.0, [0.0]);
    let mut got = Ok(RungeKuttaStep::default());
    for _ in 0..100 {
        got = rk.step(&mut Wall, &mut t, &mut y, None);
        if got.is_err() {
            break;
        }
    }
    match got {
        Err(Error::TrialPointRefused {
            time,
            dt,
            refusals,
            ref reason,
        }) => {
            assert!(time <= 1.0 && time + dt > 1.0, "{time} {dt}");
            assert_eq!(refusals, 3);
            assert!(reason.contains("at most 1"), "{reason}");
        }
        other => panic!("{other:?}"),
    }
    let mut rk = EmbeddedRungeKutta::new(DORMAND_PRINCE_54, options, 1, 0.5).unwrap();
    let (mut t, mut y) = (2.0, [0.0]);
    let got = rk.step(&mut Wall, &mut t, &mut y, None);
    assert!(
        matches!(got, Err(Error::InvalidParameter { name: "t", .. })),
        "{got:?}"
    );
}

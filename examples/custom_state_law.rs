//! A user-defined state law written through `rsf_state::StateLaw`, implementing only
//! `∂ψ/∂α`, and integrated by the generic backward Euler update (paper (3.5)).
//!
//! The law: Dieterich's aging law with a finite **healing time** `T_h`,
//! `θ̇ = 1 − θ/T_h − θV/L`, i.e. in `α = ln θ`
//! `α̇ = e^{−α} − 1/T_h − V/L = −∂ψ/∂α` with `ψ = (V/L + 1/T_h) α + e^{−α}` (convex).
//! Stationary contacts no longer heal forever: at `V = 0` the state saturates at
//! `θ = T_h`. `T_h = ∞` is the aging law; dropping `e^{−α}` gives the "aging law without
//! healing".
//!
//! Run: `cargo run --release --example custom_state_law`

use rsf_state::{Aging, StateLaw};

/// Aging law with healing time `t_h` (s) and slip distance `l` (m).
#[derive(Clone)]
struct AgingWithHealingTime {
    l: f64,
    t_h: f64,
}

impl StateLaw for AgingWithHealingTime {
    // The only required method: ∂ψ/∂α in 1/s, nondecreasing in α.
    fn dpsi_dalpha(&self, alpha: f64, v: f64) -> f64 {
        v / self.l + 1.0 / self.t_h - (-alpha).exp()
    }
}

/// The "aging law without healing": `θ̇ = −θV/L`, `ψ = (V/L) α`.
#[derive(Clone)]
struct NoHealing {
    l: f64,
}

impl StateLaw for NoHealing {
    fn dpsi_dalpha(&self, _alpha: f64, v: f64) -> f64 {
        v / self.l
    }
}

// The guard every program runs under (`--help`, `--max-memory-gb`; a fixed problem that
// writes nothing but the terminal's lines).
rsf_programs::fixed_size_program! {
    name: "custom_state_law",
    memory_bytes: 1e6,
    what: "three scalar state updates",
    run: run,
}

fn run() -> Result<(), rsf_state::Error> {
    let l = 1e-5; // m
    let aging = Aging::new(l)?; // closed form (Wright omega)
    let healing = AgingWithHealingTime { l, t_h: 100.0 };
    let no_healing = NoHealing { l };

    // Slip-rate history: hold (V = 0) for 1000 s, slide at 1e-6 m/s for 100 s, hold again.
    let tau = 10.0; // s
    let mut a_aging = -10.0_f64;
    let mut a_heal = -10.0_f64;
    let mut a_noheal = -10.0_f64;
    println!(
        "{:>6} {:>9} {:>14} {:>18} {:>16}",
        "t [s]", "V [m/s]", "aging (closed)", "healing T_h=100 s", "no healing"
    );
    for n in 0..=300 {
        let t = n as f64 * tau;
        let v = if (1000.0..1100.0).contains(&t) {
            1e-6
        } else {
            0.0
        };
        if n % 20 == 0 || (100..=110).contains(&n) && n % 2 == 0 {
            println!("{t:>6.0} {v:>9.1e} {a_aging:>14.6} {a_heal:>18.6} {a_noheal:>16.6}");
        }
        a_aging = aging.update(a_aging, v, tau)?;
        a_heal = healing.update(a_heal, v, tau)?; // generic safeguarded Newton/bisection
        a_noheal = no_healing.update(a_noheal, v, tau)?;
    }
    println!(
        "\nhealing law saturates at ln T_h = {:.6} during holds; aging keeps growing like ln t.",
        healing.t_h.ln()
    );
    // The generic update agrees with the closed form for the plain aging law.
    let generic = rsf_state::generic_update(&aging, -10.0, 2e-4, 1.5e-3)?;
    let closed = aging.update(-10.0, 2e-4, 1.5e-3)?;
    println!("aging law: closed form {closed:.15}, generic {generic:.15}");
    Ok(())
}

//! The SCEC SEAS benchmark BP1-QD (Erickson & Jiang 2018, the benchmark's problem
//! description; Erickson et al. 2020, Seismol. Res. Lett. 91(2), 874–890): parameters,
//! depth-dependent friction and the spec's closed-form initial conditions
//! (docs/seas-bp1.md). Antiplane, fault on x = 0, z ≥ 0 the depth (m).

use rsf_friction::RateStateParams;

/// The 12 on-fault stations of the benchmark output, depth in m (file `fltst_dpXXX` with
/// XXX the depth in hundreds of metres).
pub const SEAS_BP1_STATION_DEPTHS: [f64; 12] = [
    0.0, 2.5e3, 5e3, 7.5e3, 10e3, 12.5e3, 15e3, 17.5e3, 20e3, 25e3, 30e3, 35e3,
];

/// BP1-QD parameters (Table 1 of the spec; SI units). [`SeasBp1::default`] is the spec.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SeasBp1 {
    /// Density ρ (kg/m³).
    pub rho: f64,
    /// Shear wave speed c_s (m/s).
    pub c_s: f64,
    /// Effective normal stress σ_n (Pa).
    pub sigma_n: f64,
    /// Direct effect a above `h_top` (dimensionless).
    pub a0: f64,
    /// Direct effect a below `h_top + h_transition`.
    pub a_max: f64,
    /// Evolution effect b (uniform).
    pub b0: f64,
    /// Characteristic slip distance D_c (m), the `l` of [`RateStateParams`].
    pub d_c: f64,
    /// Plate rate V_p (m/s): creep below `w_f` and far-side loading.
    pub v_p: f64,
    /// Initial slip rate V_init (m/s).
    pub v_init: f64,
    /// Reference slip rate V₀ (m/s).
    pub v0: f64,
    /// Reference friction coefficient f₀ (the `mu0` of [`RateStateParams`]).
    pub f0: f64,
    /// Depth H of the velocity-weakening zone (m).
    pub h_top: f64,
    /// Width h of the transition of a (m).
    pub h_transition: f64,
    /// Depth W_f of the frictional fault (m); creep at V_p below.
    pub w_f: f64,
}

impl Default for SeasBp1 {
    fn default() -> Self {
        Self {
            rho: 2670.0,
            c_s: 3464.0,
            sigma_n: 50e6,
            a0: 0.010,
            a_max: 0.025,
            b0: 0.015,
            d_c: 0.008,
            v_p: 1e-9,
            v_init: 1e-9,
            v0: 1e-6,
            f0: 0.6,
            h_top: 15e3,
            h_transition: 3e3,
            w_f: 40e3,
        }
    }
}

impl SeasBp1 {
    /// Checks that every parameter is finite and all but `f0` are positive (`a0 > a_max`
    /// is allowed: any a(z) profile of this shape).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) naming the field.
    pub fn validate(&self) -> crate::Result<()> {
        let fields = [
            ("rho", self.rho),
            ("c_s", self.c_s),
            ("sigma_n", self.sigma_n),
            ("a0", self.a0),
            ("a_max", self.a_max),
            ("b0", self.b0),
            ("d_c", self.d_c),
            ("v_p", self.v_p),
            ("v_init", self.v_init),
            ("v0", self.v0),
            ("h_top", self.h_top),
            ("h_transition", self.h_transition),
            ("w_f", self.w_f),
        ];
        for (name, v) in fields {
            if !(v.is_finite() && v > 0.0) {
                return Err(crate::error::invalid(
                    name,
                    format!("{v} must be positive and finite"),
                ));
            }
        }
        if !self.f0.is_finite() {
            return Err(crate::error::invalid("f0", "must be finite"));
        }
        Ok(())
    }

    /// Shear modulus μ = ρ c_s² (Pa); 32.038 GPa for the spec.
    pub fn shear_modulus(&self) -> f64 {
        self.rho * self.c_s * self.c_s
    }

    /// Radiation damping η = μ/(2c_s) (Pa·s/m).
    pub fn radiation_damping(&self) -> f64 {
        self.shear_modulus() / (2.0 * self.c_s)
    }

    /// a(z): `a0` above H, linear to `a_max` at H + h, `a_max` below (z in m).
    pub fn a(&self, z: f64) -> f64 {
        if z < self.h_top {
            self.a0
        } else if z < self.h_top + self.h_transition {
            self.a0 + (self.a_max - self.a0) * (z - self.h_top) / self.h_transition
        } else {
            self.a_max
        }
    }

    /// The rate-and-state parameters at depth `z` (m) for the regularised law
    /// [`AsinhLaw`](rsf_friction::AsinhLaw): `mu0 = f0`, `a = a(z)`, `b = b0`,
    /// `l = D_c`.
    pub fn params(&self, z: f64) -> RateStateParams {
        RateStateParams {
            mu0: self.f0,
            a: self.a(z),
            b: self.b0,
            v0: self.v0,
            l: self.d_c,
            sigma_n: self.sigma_n,
        }
    }

    /// Uniform prestress τ₀ = σ_n a_max asinh[V_init/(2V₀) exp((f₀ + b₀ ln(V₀/V_init))/a_max)]
    /// + η V_init (Pa): steady state at V_init where a = a_max.
    pub fn tau0(&self) -> f64 {
        let q = (self.f0 + self.b0 * (self.v0 / self.v_init).ln()) / self.a_max;
        self.sigma_n * self.a_max * (self.v_init / (2.0 * self.v0) * q.exp()).asinh()
            + self.radiation_damping() * self.v_init
    }

    /// Initial state θ(z, 0) = (D_c/V₀) exp[(a/b) ln((2V₀/V_init) sinh((τ₀ − ηV_init)/(aσ_n)))
    /// − f₀/b] (s), so that F(V_init, θ) = τ₀ − η V_init at every depth. Returned as
    /// `α = ln θ` (sinh is evaluated in log form: no overflow for small a).
    pub fn alpha0(&self, z: f64) -> f64 {
        let a = self.a(z);
        let x = (self.tau0() - self.radiation_damping() * self.v_init) / (a * self.sigma_n);
        // ln sinh x = x + ln((1 − e^{−2x})/2), x > 0.
        let ln_sinh = x + (-(-2.0 * x).exp_m1()).ln() - std::f64::consts::LN_2;
        (self.d_c / self.v0).ln() + (a / self.b0) * ((2.0 * self.v0 / self.v_init).ln() + ln_sinh)
            - self.f0 / self.b0
    }

    /// Name of the station file at `depth` (m): `fltst_dp` and the depth in hundreds of
    /// metres, three digits (`fltst_dp025` for 2.5 km).
    pub fn station_name(depth: f64) -> String {
        format!("fltst_dp{:03}", (depth / 100.0).round() as i64)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rsf_friction::{AsinhLaw, FrictionLaw};

    #[test]
    fn material_constants() {
        let s = SeasBp1::default();
        assert!((s.shear_modulus() / 32.038e9 - 1.0).abs() < 1e-4);
        assert!((s.radiation_damping() - 2670.0 * 3464.0 / 2.0).abs() < 1e-6);
    }

    #[test]
    fn a_of_depth_is_continuous_and_matches_the_table() {
        let s = SeasBp1::default();
        assert_eq!(s.a(0.0), 0.010);
        assert_eq!(s.a(14_999.0), 0.010);
        assert!((s.a(16.5e3) - 0.0175).abs() < 1e-15);
        assert_eq!(s.a(18e3), 0.025);
        assert_eq!(s.a(39e3), 0.025);
        for z in [15e3, 18e3] {
            assert!((s.a(z - 1e-6) - s.a(z)).abs() < 1e-11, "jump at {z}");
        }
    }

    /// The spec's θ₀ closed form against the library's regularised law (an independent
    /// evaluation): σ_n F(V_init, θ₀(z)) = τ₀ − η V_init at every depth.
    #[test]
    fn initial_state_balances_the_prestress_at_every_depth() {
        let s = SeasBp1::default();
        let target = s.tau0() - s.radiation_damping() * s.v_init;
        for i in 0..=80 {
            let z = i as f64 * 500.0;
            let law = AsinhLaw::new(s.params(z)).unwrap();
            let f = s.sigma_n * law.friction_coefficient(s.v_init, s.alpha0(z));
            assert!(
                (f - target).abs() <= 1e-12 * target,
                "z = {z}: {f} vs {target}"
            );
        }
    }

    /// Below H + h (a = a_max) the initial state is steady state at V_init: θ₀ = D_c/V_init
    /// (the aging law's θ̇ = 1 − Vθ/D_c vanishes); above it is not.
    #[test]
    fn initial_state_is_steady_where_a_is_a_max() {
        let s = SeasBp1::default();
        let ss = (s.d_c / s.v_init).ln();
        for z in [18e3, 25e3, 39.9e3] {
            assert!((s.alpha0(z) - ss).abs() < 1e-10, "z = {z}");
        }
        assert!((s.alpha0(5e3) - ss).abs() > 1.0);
        // τ₀ − ηV_init is the steady-state regularised friction at V_init with a_max,
        // which for V ≫ V_m is within 1e-12 of the Dieterich–Ruina steady state.
        let p = s.params(30e3);
        let mu_ss = p.steady_state_friction(s.v_init);
        let tau = s.tau0() - s.radiation_damping() * s.v_init;
        assert!(
            (tau / s.sigma_n - mu_ss).abs() < 1e-9,
            "{} {mu_ss}",
            tau / s.sigma_n
        );
    }

    #[test]
    fn invalid_parameters_name_the_field() {
        assert!(SeasBp1::default().validate().is_ok());
        let s = SeasBp1 {
            d_c: -1.0,
            ..SeasBp1::default()
        };
        let e = s.validate().unwrap_err().to_string();
        assert!(e.contains("d_c"), "{e}");
        let s = SeasBp1 {
            f0: f64::NAN,
            ..SeasBp1::default()
        };
        assert!(s.validate().unwrap_err().to_string().contains("f0"));
    }

    #[test]
    fn station_names_are_the_spec_list() {
        let names: Vec<String> = SEAS_BP1_STATION_DEPTHS
            .iter()
            .map(|&d| SeasBp1::station_name(d))
            .collect();
        let spec = [
            "000", "025", "050", "075", "100", "125", "150", "175", "200", "250", "300", "350",
        ];
        for (n, s) in names.iter().zip(spec) {
            assert_eq!(n, &format!("fltst_dp{s}"));
        }
    }
}

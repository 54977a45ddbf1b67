//! The files written whole: the stations', `global.dat`, the profiles, `rupture.dat` and
//! the catalogue `events.csv`.

use std::fmt::Write as _;

use rsf::checkpoint::write_atomically;

use super::text::{NEVER_RUPTURED, RUPTURE_THRESHOLD};
use super::SeasBp5Output;
use crate::error::Result;
use crate::text::{c_exp, File, FileLayout};

impl SeasBp5Output {
    /// Every file of rows: stations on and off the fault, `global.dat`, the profiles.
    pub(super) fn files(&self) -> impl Iterator<Item = &File> {
        self.fault
            .iter()
            .map(|s| &s.file)
            .chain(self.body.iter().map(|s| &s.file))
            .chain(std::iter::once(&self.global))
            .chain(self.profiles.iter().map(|p| &p.file))
    }

    /// Writes every file whole (atomically) and the catalogue, into the space held for
    /// them (given back first).
    pub(super) fn write_files(&mut self) -> Result<()> {
        self.reserve.release()?;
        self.write_all_files()
    }

    /// [`write_files`](Self::write_files)' writing.
    fn write_all_files(&self) -> Result<()> {
        let steps = (self.mark.steps > 0).then_some(self.mark.tau);
        let written = (self.mark.written, self.mark.profile_written);
        for f in self.files() {
            f.write(&self.setup, steps, written)?;
        }
        if self.spec.rupture.is_some() {
            self.write_rupture()?;
        }
        if !self.spec.catalogue {
            return Ok(());
        }
        let mut csv = String::from(
            "event,t_start_s,t_end_s,peak_slip_rate_mps,hypocentre_x2_m,hypocentre_x3_m\n",
        );
        for (i, e) in self.mark.events.iter().enumerate() {
            let _ = writeln!(
                csv,
                "{},{:e},{:e},{:e},{},{}",
                i + 1,
                e.t_start,
                e.t_end.unwrap_or(f64::NAN),
                e.peak_slip_rate,
                e.hypocentre[0],
                e.hypocentre[1]
            );
        }
        Ok(write_atomically(
            &self.dir.join("events.csv"),
            csv.as_bytes(),
        )?)
    }

    /// `rupture.dat`: per fault node `x2 x3 t` (m, m, s), the first time (after the first
    /// event for BP5) that its slip rate reached [`RUPTURE_THRESHOLD`] ([`NEVER_RUPTURED`]
    /// if it did not).
    fn write_rupture(&self) -> Result<()> {
        let steps = (self.mark.steps > 0).then_some(self.mark.tau);
        let after = if self.spec.rupture == Some(true) {
            " after the first event"
        } else {
            ""
        };
        let location = format!(
            "on fault, the first time{after} that each node's slip rate reached \
             {RUPTURE_THRESHOLD:e} m/s ({NEVER_RUPTURED:e} s: never)"
        );
        let columns = [("x2", "x2 (m)"), ("x3", "x3 (m)"), ("t", "t (s)")];
        let mut text = FileLayout::new(location, &columns).header(
            &self.setup,
            steps,
            self.layout.positions.len(),
        );
        text.push('\n');
        for (x, t) in self.layout.positions.iter().zip(&self.mark.rupture) {
            let _ = writeln!(
                text,
                "{} {} {}",
                c_exp(x[0], 6, 14),
                c_exp(x[1], 6, 14),
                c_exp(t.unwrap_or(NEVER_RUPTURED), 13, 21)
            );
        }
        Ok(write_atomically(
            &self.dir.join("rupture.dat"),
            text.as_bytes(),
        )?)
    }
}

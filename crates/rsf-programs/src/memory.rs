//! The process's resident memory as Linux reports it (`/proc/self/status`: `VmRSS`, and
//! `VmHWM`, the peak that `/usr/bin/time -v` prints as "Maximum resident set size"), and
//! the peak of one stage of work: [`StageMemory`] resets the peak (`/proc/self/clear_refs`,
//! Linux ≥ 4.0) before each stage and reads it after. Elsewhere every reading is `None`.

use std::time::Instant;

/// A field of `/proc/self/status` in bytes (`None` off Linux or if unreadable).
fn status_bytes(field: &str) -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with(field))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// The process's peak resident memory since it started or since the last
/// [`reset_peak`] (bytes; `VmHWM`).
pub fn peak_bytes() -> Option<u64> {
    status_bytes("VmHWM:")
}

/// The process's resident memory now (bytes; `VmRSS`).
pub fn resident_bytes() -> Option<u64> {
    status_bytes("VmRSS:")
}

/// Resets the peak [`peak_bytes`] reads to the resident memory now; `false` if the
/// system does not allow it (then the peak keeps counting from the start).
pub fn reset_peak() -> bool {
    std::fs::write("/proc/self/clear_refs", "5").is_ok()
}

/// One stage's reading: its name, wall time, the peak resident memory during it (or so
/// far, see [`StageMemory::start`]) and the resident memory at its end (bytes; `None`
/// where the system reports nothing).
#[derive(Debug, Clone, PartialEq)]
pub struct StageReading {
    /// The stage.
    pub stage: String,
    /// Wall time of the stage (s).
    pub seconds: f64,
    /// Peak resident memory during the stage, or of the process so far (bytes).
    pub peak: Option<u64>,
    /// Resident memory at the end of the stage (bytes).
    pub resident: Option<u64>,
}

/// The readings of consecutive stages: [`start`](Self::start), then
/// [`end`](Self::end) with each stage's name as it ends (the next stage starts then).
#[derive(Debug)]
pub struct StageMemory {
    since: Instant,
    /// Whether each stage's peak is its own (the peak reset before it) rather than the
    /// process's so far.
    pub per_stage: bool,
    /// The stages read so far, in order.
    pub readings: Vec<StageReading>,
}

impl StageMemory {
    /// Starts the first stage now. With `per_stage`, the process's peak is reset before
    /// every stage (where the system allows it), so that each reading is that stage's
    /// own peak — and the peak `/usr/bin/time -v` reports at the end is then only the
    /// last stage's; without, each reading is the peak so far and the process's peak
    /// stays whole.
    pub fn start(per_stage: bool) -> Self {
        Self {
            since: Instant::now(),
            per_stage: per_stage && reset_peak(),
            readings: Vec::new(),
        }
    }

    /// Ends the current stage, named `stage`, and starts the next.
    pub fn end(&mut self, stage: impl Into<String>) {
        self.readings.push(StageReading {
            stage: stage.into(),
            seconds: self.since.elapsed().as_secs_f64(),
            peak: peak_bytes(),
            resident: resident_bytes(),
        });
        if self.per_stage {
            self.per_stage = reset_peak();
        }
        self.since = Instant::now();
    }

    /// The largest peak of the stages read (bytes).
    pub fn peak(&self) -> Option<u64> {
        self.readings.iter().filter_map(|r| r.peak).max()
    }

    /// The readings as a Markdown table (MB), headed `| stage | wall (s) | peak (MB) |
    /// resident after (MB) |` (the peak "so far" unless each stage's own).
    pub fn table(&self) -> String {
        let mb = |b: Option<u64>| b.map_or("—".to_string(), |b| format!("{:.0}", b as f64 / 1e6));
        let peak = if self.per_stage {
            "peak in the stage"
        } else {
            "peak so far"
        };
        let mut out = format!("| stage | wall (s) | {peak} (MB) | resident after (MB) |\n");
        out.push_str("|---|---|---|---|\n");
        for r in &self.readings {
            out.push_str(&format!(
                "| {} | {:.2} | {} | {} |\n",
                r.stage,
                r.seconds,
                mb(r.peak),
                mb(r.resident)
            ));
        }
        out
    }
}

//! What a checkpoint continues: the run's physics and method as `field = value` pairs.

use crate::error::{Error, Result};

/// The name of the checkpoints' content that this version continues (the `format` of a
/// [`Fingerprint`]): `RSFCKPT3`, the state of a run as the format of that name laid it out.
/// `RSFCKPT4` (with a method's state) and `RSFCKPT5` (the same content through serde) carry
/// it unchanged, so a run checkpointed in either resumes in the other.
pub const CHECKPOINT_FORMAT: &str = "RSFCKPT3";

/// What a checkpoint continues: the physics and method of the run that wrote it, as
/// `field = value` pairs in the order given (e.g. `SliderScene::fingerprint`:
/// every scene field, the format). A run checks a checkpoint's fingerprint against its
/// own before it resumes ([`check`](Self::check)).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Fingerprint(pub Vec<(String, String)>);

impl Fingerprint {
    /// The fingerprint with `field = value` appended. Newlines and `=` in the field are
    /// replaced by spaces and newlines in the value by `\n`, so that it round-trips.
    pub fn with(mut self, field: &str, value: impl std::fmt::Display) -> Self {
        let field = field.replace(['\n', '='], " ");
        let value = value.to_string().replace('\n', "\\n");
        self.0.push((field, value));
        self
    }

    /// The fields of a serialisable value (e.g. a scene) as JSON names and renders them:
    /// nested fields joined by `.`, array entries by their index, values in JSON (numbers
    /// exactly, as the shortest text that reads back to the same double).
    pub fn of_serialized(value: &impl serde::Serialize) -> Self {
        fn flatten(prefix: &str, v: &serde_json::Value, out: &mut Fingerprint) {
            let join = |k: &str| {
                if prefix.is_empty() {
                    k.to_owned()
                } else {
                    format!("{prefix}.{k}")
                }
            };
            match v {
                serde_json::Value::Object(m) => {
                    for (k, x) in m {
                        flatten(&join(k), x, out);
                    }
                }
                serde_json::Value::Array(a) => {
                    for (i, x) in a.iter().enumerate() {
                        flatten(&join(&i.to_string()), x, out);
                    }
                }
                x => out
                    .0
                    .push((prefix.replace(['\n', '='], " "), x.to_string())),
            }
        }
        let mut out = Self::default();
        match serde_json::to_value(value) {
            Ok(v) => flatten("", &v, &mut out),
            Err(e) => out.0.push(("unserialisable".into(), e.to_string())),
        }
        out
    }

    /// The value of `field`, if present.
    pub fn get(&self, field: &str) -> Option<&str> {
        self.0
            .iter()
            .find(|(f, _)| f == field)
            .map(|(_, v)| v.as_str())
    }

    /// Checks that a checkpoint with this fingerprint continues a run with fingerprint
    /// `run`: every field of either is present in both with the same value, except the
    /// fields named in `allowed` (deliberate changes, e.g. a later `end_time_s`).
    ///
    /// # Errors
    /// [`Error::CheckpointMismatch`] naming the first differing field (a missing field is
    /// shown as `absent`; an empty fingerprint, of a checkpoint of an earlier format, as
    /// the field `format`).
    pub fn check(&self, run: &Fingerprint, allowed: &[&str]) -> Result<()> {
        let mismatch = |field: &str, c: Option<&str>, r: Option<&str>| Error::CheckpointMismatch {
            field: rsf_numeric::excerpt(field),
            checkpoint: rsf_numeric::excerpt(c.unwrap_or("absent")),
            run: rsf_numeric::excerpt(r.unwrap_or("absent")),
        };
        if self.0.is_empty() && !allowed.contains(&"format") {
            return Err(mismatch(
                "format",
                Some("an earlier format without fingerprint"),
                Some(CHECKPOINT_FORMAT),
            ));
        }
        for (field, value) in &run.0 {
            let mine = self.get(field);
            if mine != Some(value.as_str()) && !allowed.contains(&field.as_str()) {
                return Err(mismatch(field, mine, Some(value)));
            }
        }
        for (field, value) in &self.0 {
            if run.get(field).is_none() && !allowed.contains(&field.as_str()) {
                return Err(mismatch(field, Some(value), None));
            }
        }
        Ok(())
    }

    /// The `field=value` lines of the formats 3 and 4 (written by the tests only).
    #[cfg(test)]
    pub(super) fn to_text(&self) -> String {
        self.0.iter().map(|(f, v)| format!("{f}={v}\n")).collect()
    }

    /// The fingerprint of [`to_text`](Self::to_text)'s lines.
    pub(super) fn from_text(text: &str) -> Option<Self> {
        text.lines()
            .map(|l| l.split_once('=').map(|(f, v)| (f.to_owned(), v.to_owned())))
            .collect::<Option<Vec<_>>>()
            .map(Self)
    }
}

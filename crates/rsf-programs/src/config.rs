//! `--config FILE.toml`: a program's run configuration ([`rsf_scenes::RunConfig`]) from a
//! TOML file, the flags given on the command line over the file's keys, the defaults under
//! both; a refused setting named as the user wrote it (the flag, or the file's key).

use std::path::PathBuf;

use clap::parser::ValueSource;
use rsf_scenes::run_config::merge_file;
use rsf_scenes::RunConfig;

use crate::guard::AnyError;

/// The flag `--config FILE.toml` of a program with a run configuration.
#[derive(Debug, Clone, Default, clap::Args)]
pub struct ConfigArgs {
    /// A TOML file of the run's settings: keys are the flags' names with underscores
    /// (`end_years = 5`, `law = "slip"`); a flag given on the command line wins over the
    /// file's key, a key the file leaves out keeps its default. An unknown key is refused.
    #[arg(long, value_name = "FILE.toml")]
    pub config: Option<PathBuf>,
    /// The keys the file set that no flag overrode.
    #[arg(skip)]
    from_file: Vec<String>,
}

impl ConfigArgs {
    /// `flags` (the settings as clap parsed them, defaults included) with the file's keys
    /// where the flag was not given on the command line (`matches`); `flags` itself
    /// without `--config`.
    ///
    /// # Errors
    /// The file's ([`merge_file`]), named `--config FILE`.
    pub fn merged<C: RunConfig>(
        &mut self,
        flags: C,
        matches: &clap::ArgMatches,
    ) -> Result<C, AnyError> {
        let Some(path) = &self.config else {
            return Ok(flags);
        };
        let given = |key: &str| {
            matches.try_contains_id(key).unwrap_or(false)
                && matches.value_source(key) == Some(ValueSource::CommandLine)
        };
        let (run, from_file) = merge_file(path, &flags, given).map_err(|e| self.on_file(e))?;
        self.from_file = from_file;
        Ok(run)
    }

    /// Checks `run` ([`RunConfig::validate`]), a refused setting named as the user wrote
    /// it: `--config FILE: key `dx`: …` if the file set it, else its flag (`--dx 3: …`).
    ///
    /// # Errors
    /// The first refused setting.
    pub fn validate<C: RunConfig>(&self, run: &C) -> Result<(), AnyError> {
        run.validate().map_err(|e| self.named(e))
    }

    /// `e` named as the user wrote the setting it names: a refused value as its file key
    /// or flag; an ill-conditioned model's fields to change likewise.
    pub fn named(&self, e: rsf::Error) -> AnyError {
        match e {
            rsf::Error::InvalidParameter { name, reason } => {
                if self.from_file.contains(&name) {
                    format!("{}: key `{name}` = {reason}", self.file_name()).into()
                } else {
                    format!("--{} {reason}", name.replace('_', "-")).into()
                }
            }
            rsf::Error::IllConditioned { fields, reason } => rsf::Error::IllConditioned {
                fields: fields
                    .into_iter()
                    .map(|f| {
                        if self.from_file.contains(&f) {
                            format!("`{f}` of {}", self.file_name())
                        } else {
                            format!("--{}", f.replace('_', "-"))
                        }
                    })
                    .collect(),
                reason,
            }
            .into(),
            e => e.into(),
        }
    }

    /// The keys the file set that no flag overrode (after
    /// [`merged`](Self::merged)), sorted.
    pub fn from_file(&self) -> &[String] {
        &self.from_file
    }

    /// `--config FILE` as messages show it.
    fn file_name(&self) -> String {
        let path = self.config.as_deref().unwrap_or(std::path::Path::new(""));
        format!(
            "--config {}",
            rsf_numeric::excerpt(&path.display().to_string())
        )
    }

    /// An error of the file, named `--config FILE` unless it names the path already.
    fn on_file(&self, e: rsf::Error) -> AnyError {
        format!("--config: {e}").into()
    }
}

/// `command` with the defaults of the flags named by `settings`' fields (their TOML keys)
/// set to `settings`' values ([`rsf_scenes::run_config::flag_defaults`]): a program whose
/// settings start from another value than the struct's [`Default`] (the 3-D slider's scene
/// over the 2-D slider's, a figure's scene) shows and parses its own defaults. Keys
/// without a flag are left alone.
pub fn with_defaults(command: clap::Command, settings: &impl serde::Serialize) -> clap::Command {
    rsf_scenes::run_config::flag_defaults(settings)
        .into_iter()
        .fold(command, |command, (key, value)| {
            let has_flag = command
                .get_arguments()
                .any(|a| a.get_id().as_str() == key.as_str());
            if has_flag {
                command.mut_arg(key, |a| a.default_value(value))
            } else {
                command
            }
        })
}

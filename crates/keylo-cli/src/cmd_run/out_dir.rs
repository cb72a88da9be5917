//! Where `keylo run` writes: `--out`, `[output] dir`, or `runs/<UTC time>/`.

use std::path::PathBuf;

use anyhow::{Context, Result};
use keylo::config::PipelineConfig;

use super::args::RunArgs;

pub(super) fn output_dir(args: &RunArgs, config: &PipelineConfig) -> Result<PathBuf> {
    let dir = match (&args.out, config.output.dir_path()) {
        (Some(d), _) => d.clone(),
        (None, Some(d)) => config.base_dir.join(d),
        (None, None) => {
            let secs = std::time::SystemTime::now()
                .duration_since(std::time::UNIX_EPOCH)
                .map_or(0, |d| d.as_secs());
            PathBuf::from("runs").join(timestamp_name(secs))
        }
    };
    std::fs::create_dir_all(&dir)
        .with_context(|| format!("creating output directory {}", dir.display()))?;
    Ok(dir)
}

/// `YYYYMMDD-HHMMSS` (UTC) of a Unix time.
fn timestamp_name(secs: u64) -> String {
    let days = secs / 86_400;
    let rem = secs % 86_400;
    // civil-from-days (Howard Hinnant's algorithm)
    let z = days as i64 + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    format!(
        "{y:04}{m:02}{d:02}-{:02}{:02}{:02}",
        rem / 3600,
        (rem / 60) % 60,
        rem % 60
    )
}

#[cfg(test)]
mod tests {
    #[test]
    fn timestamps_are_civil_dates() {
        assert_eq!(super::timestamp_name(0), "19700101-000000");
        assert_eq!(super::timestamp_name(1_795_000_000), "20261118-110640");
    }
}

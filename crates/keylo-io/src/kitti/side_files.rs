//! The text files beside KITTI scans: `times.txt` (one time per scan, seconds) and
//! `calib.txt` (`KEY: numbers` lines; `Tr:` is the Velodyne → cam0 transform).

use std::path::Path;

use keylo_core::Pose;

use crate::IoError;

/// Reads `times.txt`: one number per line (blank lines skipped); the error names the line.
pub fn read_times(path: &Path) -> Result<Vec<f64>, IoError> {
    let text = std::fs::read_to_string(path).map_err(|e| IoError::io(path, e))?;
    let mut times = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let tokens: Vec<&str> = line.split_whitespace().collect();
        match tokens.as_slice() {
            [] => continue,
            [t] => times.push(number(t).map_err(|m| line_error(path, i + 1, m))?),
            more => {
                let m = format!("expected one time (seconds), found {} values", more.len());
                return Err(line_error(path, i + 1, m));
            }
        }
    }
    Ok(times)
}

/// Reads `calib.txt` and returns its `Tr` (Velodyne → cam0), `None` when it has no `Tr:`
/// line. Every line must be `KEY: numbers`; the error names the line.
pub fn read_calib_tr(path: &Path) -> Result<Option<Pose>, IoError> {
    let text = std::fs::read_to_string(path).map_err(|e| IoError::io(path, e))?;
    let mut tr = None;
    for (i, line) in text.lines().enumerate() {
        let n = i + 1;
        if line.trim().is_empty() {
            continue;
        }
        let Some((key, values)) = line.split_once(':') else {
            return Err(line_error(path, n, "expected `KEY: numbers`"));
        };
        for (c, token) in values.split_whitespace().enumerate() {
            number(token).map_err(|m| line_error(path, n, format!("value {}: {m}", c + 1)))?;
        }
        if key.trim() == "Tr" && tr.is_none() {
            tr = Some(kitti_matrix(path, n, values)?);
        }
    }
    Ok(tr)
}

/// The 12 numbers of line `line` of `path` as a pose, checked and re-orthonormalised by
/// the KITTI pose reader of [`crate::trajectory`] (the same rules as a pose file line).
fn kitti_matrix(path: &Path, line: usize, values: &str) -> Result<Pose, IoError> {
    // Blank lines in front keep the reader's line numbers those of the file.
    let text = format!("{}{values}\n", "\n".repeat(line - 1));
    let label = path.display().to_string();
    let traj = crate::trajectory::parse_kitti(&text, &label)
        .map_err(|e| trajectory_error(path, &label, &e))?;
    traj.poses
        .first()
        .copied()
        .ok_or_else(|| line_error(path, line, "expected 12 numbers"))
}

/// A trajectory-file error as an error of `path`, without repeating the file name.
pub(crate) fn trajectory_error(
    path: &Path,
    label: &str,
    e: &crate::trajectory::TrajectoryError,
) -> IoError {
    let message = e.to_string();
    let rest = message
        .strip_prefix(label)
        .unwrap_or(&message)
        .trim_start_matches(':')
        .trim_start();
    IoError::format(path, rest)
}

fn number(token: &str) -> Result<f64, String> {
    match token.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        Ok(_) => Err(format!("'{token}' is not finite")),
        Err(_) => Err(format!("'{token}' is not a number")),
    }
}

fn line_error(path: &Path, line: usize, message: impl std::fmt::Display) -> IoError {
    IoError::format(path, format!("line {line}: {message}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(dir: &Path, name: &str, text: &str) -> std::path::PathBuf {
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        p
    }

    #[test]
    fn times_are_read_and_bad_lines_named() {
        let d = tempfile::tempdir().unwrap();
        let p = write(d.path(), "times.txt", "0.0\n\n1.0e-1\n");
        assert_eq!(read_times(&p).unwrap(), vec![0.0, 0.1]);
        let p = write(d.path(), "bad.txt", "0.0\n0.1 0.2\n");
        let e = read_times(&p).unwrap_err().to_string();
        assert!(
            e.ends_with("bad.txt: line 2: expected one time (seconds), found 2 values"),
            "{e}"
        );
        let p = write(d.path(), "nan.txt", "x\n");
        assert!(read_times(&p)
            .unwrap_err()
            .to_string()
            .contains("line 1: 'x' is not a number"));
    }

    #[test]
    fn calib_tr_is_read_and_malformed_lines_are_named() {
        let d = tempfile::tempdir().unwrap();
        let tr = "Tr: 0 -1 0 0.1 0 0 -1 0.2 1 0 0 0.3\n";
        let p = write(d.path(), "calib.txt", &format!("P0: 1 0 0 0\n{tr}"));
        let pose = read_calib_tr(&p).unwrap().unwrap();
        assert_eq!(pose.translation.vector.z, 0.3);
        let p = write(d.path(), "none.txt", "P0: 1 2\n");
        assert!(read_calib_tr(&p).unwrap().is_none());
        let p = write(d.path(), "short.txt", "P0: 1\nTr: 1 0 0 0 0 1 0 0 0 0 1\n");
        let e = read_calib_tr(&p).unwrap_err().to_string();
        assert!(
            e.ends_with("short.txt: line 2: expected 12 numbers, found 11"),
            "{e}"
        );
        let p = write(d.path(), "junk.txt", "P0: 1 zz\n");
        let e = read_calib_tr(&p).unwrap_err().to_string();
        assert!(
            e.ends_with("junk.txt: line 1: value 2: 'zz' is not a number"),
            "{e}"
        );
        let p = write(d.path(), "nokey.txt", "\n1 2 3\n");
        assert!(read_calib_tr(&p)
            .unwrap_err()
            .to_string()
            .contains("line 2: expected `KEY"));
    }
}

//! `keylo convert INPUT --format F --out DIR`: the frames of any source as files other tools
//! read, with `times.txt` (seconds since the first frame, one line per frame, as KITTI).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{bail, Context, Result};
use keylo::io::export::pcd::write_pcd;
use keylo::io::export::ply::write_ply;
use keylo::io::export::{ExportField, ExportPoints};
use keylo::io::frames::FramesWriter;
use keylo::io::kitti_bin::write_kitti_bin_points;
use keylo::LidarFrame;

use clap::{Args, ValueEnum};

use crate::arg_groups::DataArgs;
use crate::{configs, EXIT_FRAME_FAILED};

pub fn run(args: ConvertArgs, quiet: bool) -> Result<ExitCode> {
    let fields = fields(&args)?;
    let mut registry = keylo::registry();
    let (_, mut source) = configs::open_data(&mut registry, &args.data)?;
    let description = source.info().description;
    let dir = match args.format {
        ConvertFormat::KittiBin => args.out.join("velodyne"),
        _ => args.out.clone(),
    };
    std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
    let mut writer = Writer {
        args: &args,
        dir,
        fields,
        frames: None,
        times: String::new(),
        first: None,
        count: 0,
    };
    let mut failure = None;
    while let Some(frame) = source.next_frame() {
        match frame {
            Ok(f) => writer.write(&f, &description)?,
            Err(e) => {
                failure = Some(format!("frame {}: {e}", writer.count));
                break;
            }
        }
    }
    let count = writer.count;
    writer.finish()?;
    if !quiet {
        println!("wrote {count} frames to {}", args.out.display());
    }
    Ok(match failure {
        Some(e) => {
            eprintln!("error: {e} (the {count} frames before it are written)");
            ExitCode::from(EXIT_FRAME_FAILED)
        }
        None if count == 0 => bail!("{}: the source holds no frame", args.data.data.display()),
        None => ExitCode::SUCCESS,
    })
}

fn fields(args: &ConvertArgs) -> Result<Vec<ExportField>> {
    let parsed: Vec<ExportField> = args
        .channels
        .iter()
        .map(|c| c.trim().parse().map_err(anyhow::Error::msg))
        .collect::<Result<_>>()
        .context("--channels")?;
    Ok(match (args.format, parsed.is_empty()) {
        (ConvertFormat::KittiBin, true) => vec![ExportField::Signal],
        (ConvertFormat::KittiBin, false) if parsed.len() != 1 => {
            bail!("--channels: KITTI .bin holds x y z and exactly one channel")
        }
        (_, true) => ExportField::ALL.to_vec(),
        _ => parsed,
    })
}

struct Writer<'a> {
    args: &'a ConvertArgs,
    dir: PathBuf,
    fields: Vec<ExportField>,
    frames: Option<FramesWriter>,
    times: String,
    first: Option<f64>,
    count: usize,
}

impl Writer<'_> {
    fn write(&mut self, frame: &LidarFrame, description: &str) -> Result<()> {
        let name = |ext: &str| self.dir.join(format!("{:06}.{ext}", self.count));
        let points = ExportPoints::new(frame, &self.fields);
        match self.args.format {
            ConvertFormat::KittiBin => {
                write_kitti_bin_points(&name("bin"), &points)?;
            }
            ConvertFormat::Ply => {
                let comment = format!("keylo convert: {description}\nframe {}", frame.index);
                write_ply(&name("ply"), &points, &comment)?;
            }
            ConvertFormat::Pcd => {
                write_pcd(&name("pcd"), &points)?;
            }
            ConvertFormat::Frames => self.write_frame(frame, description)?,
        }
        let t0 = *self.first.get_or_insert(frame.timestamp);
        writeln!(self.times, "{:.9}", frame.timestamp - t0)?;
        self.count += 1;
        Ok(())
    }

    fn write_frame(&mut self, frame: &LidarFrame, description: &str) -> Result<()> {
        if self.frames.is_none() {
            let w = FramesWriter::create(
                &self.dir,
                frame.rows,
                frame.cols,
                (*frame.beams).clone(),
                &format!("keylo convert: {description}"),
            )?;
            self.frames = Some(w);
        }
        if let Some(w) = self.frames.as_mut() {
            w.write(frame)?;
        }
        Ok(())
    }

    fn finish(self) -> Result<()> {
        if let Some(w) = self.frames {
            w.finish()?;
        }
        let path: &Path = &self.args.out;
        let times = path.join("times.txt");
        std::fs::write(&times, &self.times).with_context(|| format!("writing {}", times.display()))
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ConvertFormat {
    /// KITTI velodyne .bin: x y z + one channel (float32), in velodyne/.
    KittiBin,
    /// Binary little-endian PLY, one file per frame.
    Ply,
    /// Binary PCD v0.7, one file per frame.
    Pcd,
    /// keylo frame folder (every channel, the organised grid).
    Frames,
}

#[derive(Debug, Args)]
pub struct ConvertArgs {
    #[command(flatten)]
    pub data: DataArgs,
    /// Output format.
    #[arg(long, value_enum)]
    pub format: ConvertFormat,
    /// Output folder.
    #[arg(long)]
    pub out: PathBuf,
    /// Per-point values besides x y z: signal, reflectivity, near-ir, range, ring, time
    /// (comma separated). PLY/PCD default: signal,reflectivity,near-ir,range,ring,time;
    /// KITTI .bin takes exactly one (default signal).
    #[arg(long, value_delimiter = ',')]
    pub channels: Vec<String>,
}

//! keylo's GICP with the command line of the PCL reference (`shared/peers/pcl_gicp`), for
//! side-by-side parity and timing:
//!
//! ```text
//! gicp_pair pair SRC TGT [opts]     register SRC onto TGT from identity; prints
//!                                   "0 x y z qx qy qz qw" and "iterations N ms T"
//! gicp_pair seq DIR OUT.tum [opts]  frame-to-previous-frame odometry over DIR/*.bin|*.ply
//! opts: --corr D (5) --k K (20) --eps E (5e-4) --reps R (2e-3) --iters N (200)
//!       --voxel V (0: none; centroid voxel filter of source and target)
//!       --cost gicp|point-to-plane --threads N (0: all cores)
//! ```
//! Clouds: KITTI `.bin` or binary little-endian float `.ply`. Time: the covariances of both
//! clouds and the alignment (what PCL's `align` does); in `seq`, as keylo's frame-to-frame
//! registrar, the previous frame's covariances are reused as the target's.

use std::path::Path;
use std::time::Instant;

use keylo_registration::gicp::{align, Cost, GicpCloud, GicpSettings};
use nalgebra::Isometry3;

#[path = "common/clouds.rs"]
mod clouds;
use clouds::{filtered, frame_files, load, pose_line};

struct Opts {
    settings: GicpSettings,
    k: usize,
    voxel: f64,
    threads: usize,
}

const EPSILON: f64 = 1e-3;

fn parse(args: &[String]) -> Result<Opts, String> {
    let mut o = Opts {
        settings: GicpSettings::default(),
        k: 20,
        voxel: 0.0,
        threads: 0,
    };
    for pair in args.chunks(2) {
        let [k, v] = pair else {
            return Err(format!("option {pair:?} needs a value"));
        };
        let num = || v.parse::<f64>().map_err(|e| format!("{k} {v}: {e}"));
        match k.as_str() {
            "--corr" => o.settings.max_correspondence_distance = num()?,
            "--k" => o.k = num()? as usize,
            "--eps" => o.settings.transformation_epsilon = num()?,
            "--reps" => o.settings.rotation_epsilon = num()?,
            "--iters" => o.settings.max_iterations = num()? as usize,
            "--voxel" => o.voxel = num()?,
            "--threads" => o.threads = num()? as usize,
            "--cost" => {
                o.settings.cost = match v.as_str() {
                    "gicp" => Cost::Gicp,
                    "point-to-plane" => Cost::PointToPlane,
                    _ => return Err(format!("unknown cost {v}")),
                }
            }
            _ => return Err(format!("unknown option {k}")),
        }
    }
    Ok(o)
}

fn cloud(path: &Path, o: &Opts) -> Result<Vec<nalgebra::Point3<f64>>, String> {
    Ok(filtered(load(path)?, o.voxel))
}

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.len() < 3 {
        return Err(
            "usage: gicp_pair pair SRC TGT [opts] | gicp_pair seq DIR OUT.tum [opts]".into(),
        );
    }
    let o = parse(&args[3..])?;
    if o.threads > 0 {
        rayon::ThreadPoolBuilder::new()
            .num_threads(o.threads)
            .build_global()
            .map_err(|e| e.to_string())?;
    }
    let prepare = |points| GicpCloud::new(points, o.k, EPSILON).map_err(|e| e.to_string());
    if args[0] == "pair" {
        let (src, tgt) = (
            cloud(Path::new(&args[1]), &o)?,
            cloud(Path::new(&args[2]), &o)?,
        );
        let t0 = Instant::now();
        let (source, target) = (prepare(src)?, prepare(tgt)?);
        let r = align(
            (&source.cloud.points, &source.patches),
            &target,
            &Isometry3::identity(),
            &o.settings,
        )
        .map_err(|e| e.to_string())?;
        let ms = t0.elapsed().as_secs_f64() * 1e3;
        println!("{}", pose_line(0.0, &r.pose));
        println!("iterations {} ms {ms:.3}", r.iterations);
        return Ok(());
    }
    let files = frame_files(&args[1])?;
    let mut out = vec![pose_line(0.0, &Isometry3::identity())];
    let (mut pose, mut vel) = (Isometry3::identity(), Isometry3::identity());
    let mut prev = prepare(cloud(files.first().ok_or("no frames")?, &o)?)?;
    let mut total = 0.0;
    for (i, f) in files.iter().enumerate().skip(1) {
        let points = cloud(f, &o)?;
        let t0 = Instant::now();
        let cur = prepare(points)?;
        let r = align((&cur.cloud.points, &cur.patches), &prev, &vel, &o.settings)
            .map_err(|e| e.to_string())?;
        total += t0.elapsed().as_secs_f64() * 1e3;
        vel = r.pose;
        pose *= vel;
        out.push(pose_line(i as f64, &pose));
        prev = cur;
    }
    std::fs::write(&args[2], out.join("\n") + "\n").map_err(|e| e.to_string())?;
    println!(
        "frames {} mean_ms {:.3}",
        files.len(),
        total / (files.len().max(2) - 1) as f64
    );
    Ok(())
}

//! keylo's NDT with the command line of the PCL reference (`shared/peers/pcl_ndt`), for
//! side-by-side parity and timing:
//!
//! ```text
//! ndt_pair pair SRC TGT [opts]     register SRC onto TGT from identity; prints
//!                                  "0 x y z qx qy qz qw" and "iterations N ms T"
//! ndt_pair seq DIR OUT.tum [opts]  frame-to-previous-frame odometry over DIR/*.bin|*.ply
//! ndt_pair voxel IN OUT.bin SIZE   centroid voxel filter, written as KITTI .bin (i = 0)
//! opts: --res R (1.0) --step S (0.1) --eps E (0.001) --iters N (35) --voxel V (0: none;
//!       centroid voxel filter of the source) --search radius|direct7|direct1
//!       --threads N (0: all cores)
//! ```
//! Clouds: KITTI `.bin` (float32 x y z i) or binary little-endian `.ply` with float
//! properties, x y z first. Time is for building the target and aligning (as PCL's).

use std::path::Path;
use std::time::Instant;

use keylo_registration::ndt::{align, AlignSettings, GridSettings, NdtTarget, NeighbourSearch};
use nalgebra::{Isometry3, Point3};

#[path = "common/clouds.rs"]
mod clouds;
use clouds::{filtered, frame_files, load, pose_line};

struct Opts {
    grid: GridSettings,
    solver: AlignSettings,
    voxel: f64,
    search: NeighbourSearch,
    threads: usize,
}

fn parse(args: &[String]) -> Result<Opts, String> {
    let mut o = Opts {
        grid: GridSettings::default(),
        solver: AlignSettings {
            transformation_epsilon: 0.001,
            ..AlignSettings::default()
        },
        voxel: 0.0,
        search: NeighbourSearch::Radius,
        threads: 0,
    };
    for pair in args.chunks(2) {
        let [k, v] = pair else {
            return Err(format!("option {pair:?} needs a value"));
        };
        let num = || v.parse::<f64>().map_err(|e| format!("{k} {v}: {e}"));
        match k.as_str() {
            "--res" => o.grid.resolution = num()?,
            "--step" => o.solver.step_size = num()?,
            "--eps" => o.solver.transformation_epsilon = num()?,
            "--iters" => o.solver.max_iterations = num()? as usize,
            "--voxel" => o.voxel = num()?,
            "--threads" => o.threads = num()? as usize,
            "--search" => {
                o.search = match v.as_str() {
                    "radius" => NeighbourSearch::Radius,
                    "direct7" => NeighbourSearch::Direct7,
                    "direct1" => NeighbourSearch::Direct1,
                    _ => return Err(format!("unknown search {v}")),
                }
            }
            _ => return Err(format!("unknown option {k}")),
        }
    }
    Ok(o)
}

fn run_align(
    src: &[Point3<f64>],
    tgt: &[Point3<f64>],
    o: &Opts,
    guess: &Isometry3<f64>,
) -> Result<(Isometry3<f64>, usize, f64), String> {
    let t0 = Instant::now();
    let target = NdtTarget::new(tgt, &o.grid, o.search).map_err(|e| e.to_string())?;
    let r = align(&target, src, guess, &o.solver).map_err(|e| e.to_string())?;
    Ok((r.pose, r.iterations, t0.elapsed().as_secs_f64() * 1e3))
}

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.len() < 3 {
        return Err("usage: ndt_pair pair SRC TGT [opts] | ndt_pair seq DIR OUT.tum [opts]".into());
    }
    if args[0] == "voxel" {
        let size: f64 = args
            .get(3)
            .and_then(|v| v.parse().ok())
            .ok_or("voxel IN OUT.bin SIZE")?;
        let pts = filtered(load(Path::new(&args[1]))?, size);
        let bytes: Vec<u8> = pts
            .iter()
            .flat_map(|p| [p.x as f32, p.y as f32, p.z as f32, 0.0f32])
            .flat_map(f32::to_le_bytes)
            .collect();
        std::fs::write(&args[2], bytes).map_err(|e| e.to_string())?;
        println!("{} points", pts.len());
        return Ok(());
    }
    let o = parse(&args[3..])?;
    if o.threads > 0 {
        rayon::ThreadPoolBuilder::new()
            .num_threads(o.threads)
            .build_global()
            .map_err(|e| e.to_string())?;
    }
    if args[0] == "pair" {
        let src = filtered(load(Path::new(&args[1]))?, o.voxel);
        let tgt = load(Path::new(&args[2]))?;
        let (pose, it, ms) = run_align(&src, &tgt, &o, &Isometry3::identity())?;
        println!("{}", pose_line(0.0, &pose));
        println!("iterations {it} ms {ms:.3}");
        return Ok(());
    }
    let files = frame_files(&args[1])?;
    let mut out = vec![pose_line(0.0, &Isometry3::identity())];
    let (mut pose, mut vel) = (Isometry3::identity(), Isometry3::identity());
    let mut prev = load(files.first().ok_or("no frames")?)?;
    let mut total = 0.0;
    for (i, f) in files.iter().enumerate().skip(1) {
        let cur = load(f)?;
        let (rel, _, ms) = run_align(&filtered(cur.clone(), o.voxel), &prev, &o, &vel)?;
        total += ms;
        vel = rel;
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

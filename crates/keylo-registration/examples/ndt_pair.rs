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

use std::path::{Path, PathBuf};
use std::time::Instant;

use keylo_registration::ndt::{align, AlignSettings, GridSettings, NdtTarget, NeighbourSearch};
use keylo_registration::voxel;
use nalgebra::{Isometry3, Point3};

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

/// KITTI `.bin` or a binary little-endian PLY whose vertex properties are all `float`.
fn load(path: &Path) -> Result<Vec<Point3<f64>>, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let (body, stride) = if path.extension().is_some_and(|e| e == "ply") {
        let end = bytes
            .windows(11)
            .position(|w| w == b"end_header\n")
            .ok_or_else(|| format!("{}: no PLY header end", path.display()))?;
        let header = String::from_utf8_lossy(&bytes[..end]);
        if !header.contains("binary_little_endian") {
            return Err(format!("{}: only binary little-endian PLY", path.display()));
        }
        let props = header.lines().filter(|l| l.starts_with("property")).count();
        if header
            .lines()
            .any(|l| l.starts_with("property") && !l.starts_with("property float "))
        {
            return Err(format!("{}: only float properties", path.display()));
        }
        (&bytes[end + 11..], 4 * props)
    } else {
        (&bytes[..], 16)
    };
    let f =
        |c: &[u8], i: usize| f64::from(f32::from_le_bytes([c[i], c[i + 1], c[i + 2], c[i + 3]]));
    Ok(body
        .chunks_exact(stride)
        .map(|c| Point3::new(f(c, 0), f(c, 4), f(c, 8)))
        .filter(|p| p.coords.iter().all(|v| v.is_finite()))
        .collect())
}

fn filtered(points: Vec<Point3<f64>>, size: f64) -> Vec<Point3<f64>> {
    if size > 0.0 {
        voxel::centroids(&points, size)
    } else {
        points
    }
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

fn pose_line(t: f64, p: &Isometry3<f64>) -> String {
    let (v, q) = (p.translation.vector, p.rotation.coords);
    format!(
        "{t:.6} {:.6} {:.6} {:.6} {:.9} {:.9} {:.9} {:.9}",
        v.x, v.y, v.z, q.x, q.y, q.z, q.w
    )
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
    let mut files: Vec<PathBuf> = std::fs::read_dir(&args[1])
        .map_err(|e| format!("{}: {e}", args[1]))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "bin" || e == "ply"))
        .collect();
    files.sort();
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

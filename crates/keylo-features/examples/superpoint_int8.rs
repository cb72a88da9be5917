//! The INT8 SuperPoint against the FP32 one on real images, for
//! `scripts/bench/superpoint_int8.sh`: keypoints reproduced and time per image, in one run.
//!
//! Usage: superpoint_int8 PNG_DIR FIRST COUNT REPEATS THREADS
//! Reads `PNG_DIR/image_NNNN.png` for NNNN in FIRST..FIRST+COUNT (8-bit grey, as the TIERS
//! signal images), resizes each to 1024×64 (linear) as the paper's configs do, and runs the
//! shipped model at both precisions with the paper's settings. Prints one JSON object: the
//! keypoints of each, the share of FP32 keypoints with an INT8 keypoint within 1 px, the mean
//! descriptor difference at those keypoints, and milliseconds per image (network, decoding and
//! descriptors; the two precisions alternate, `REPEATS` times per image).

use std::time::Instant;

use keylo_core::{BuildContext, Channel, DescriptorData, Detector, Image, Keypoint};
use keylo_features::superpoint::{ExecutionProvider, Precision, SuperPoint, SuperPointParams};
use opencv::core::{Mat, Size};
use opencv::prelude::*;

const WIDTH: i32 = 1024;
const HEIGHT: i32 = 64;

fn load(path: &str) -> Result<Image, Box<dyn std::error::Error>> {
    let mut decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path)?));
    decoder.set_transformations(png::Transformations::EXPAND);
    let mut reader = decoder.read_info()?;
    let mut buf = vec![0; reader.output_buffer_size().ok_or("image too large")?];
    let info = reader.next_frame(&mut buf)?;
    if info.color_type != png::ColorType::Grayscale || info.bit_depth != png::BitDepth::Eight {
        return Err(format!("{path}: expected an 8-bit grey PNG").into());
    }
    let full = Mat::from_slice(&buf[..info.buffer_size()])?;
    let full = full.reshape(1, i32::try_from(info.height)?)?;
    let mut small = Mat::default();
    opencv::imgproc::resize(
        &full,
        &mut small,
        Size::new(WIDTH, HEIGHT),
        0.0,
        0.0,
        opencv::imgproc::INTER_LINEAR,
    )?;
    let mut image = Image::new_gray(WIDTH as usize, HEIGHT as usize, Channel::Signal);
    image.data = small.data_bytes()?.to_vec();
    Ok(image)
}

fn model(precision: Precision, threads: usize) -> Result<SuperPoint, Box<dyn std::error::Error>> {
    let params = SuperPointParams {
        precision,
        threads,
        execution_provider: ExecutionProvider::Cpu,
        ..SuperPointParams::default()
    };
    Ok(SuperPoint::new(params, &BuildContext::default())?)
}

/// For each keypoint of `a`, the index of the nearest keypoint of `b` within 1 px.
fn within_1px(a: &[Keypoint], b: &[Keypoint]) -> Vec<Option<usize>> {
    a.iter()
        .map(|p| {
            b.iter()
                .enumerate()
                .map(|(j, q)| (j, (p.x - q.x).hypot(p.y - q.y)))
                .filter(|(_, d)| *d <= 1.0)
                .min_by(|x, y| x.1.total_cmp(&y.1))
                .map(|(j, _)| j)
        })
        .collect()
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let [_, dir, first, count, repeats, threads] = args.as_slice() else {
        return Err("usage: superpoint_int8 PNG_DIR FIRST COUNT REPEATS THREADS".into());
    };
    let (first, count): (usize, usize) = (first.parse()?, count.parse()?);
    let (repeats, threads): (usize, usize) = (repeats.parse()?, threads.parse()?);
    let mut fp32 = model(Precision::Fp32, threads)?;
    let mut int8 = model(Precision::Int8, threads)?;
    let (mut n32, mut n8, mut hit, mut desc_diff, mut pairs) = (0, 0, 0, 0.0f64, 0usize);
    let (mut ms32, mut ms8) = (0.0f64, 0.0f64);
    for i in first..first + count {
        let image = load(&format!("{dir}/image_{i:04}.png"))?;
        let (k32, d32) = fp32.run(&image)?;
        let (k8, d8) = int8.run(&image)?;
        let (DescriptorData::Float(d32), DescriptorData::Float(d8)) = (&d32.data, &d8.data) else {
            return Err("SuperPoint descriptors are float".into());
        };
        let dim = d32.len() / k32.len().max(1);
        n32 += k32.len();
        n8 += k8.len();
        for (a, b) in within_1px(&k32, &k8).into_iter().enumerate() {
            let Some(b) = b else { continue };
            hit += 1;
            let (x, y) = (&d32[a * dim..(a + 1) * dim], &d8[b * dim..(b + 1) * dim]);
            desc_diff += x
                .iter()
                .zip(y)
                .map(|(p, q)| f64::from((p - q).abs()))
                .sum::<f64>();
            pairs += dim;
        }
        for _ in 0..repeats {
            let start = Instant::now();
            std::hint::black_box(fp32.detect_and_describe(&image)?);
            ms32 += start.elapsed().as_secs_f64() * 1e3;
            let start = Instant::now();
            std::hint::black_box(int8.detect_and_describe(&image)?);
            ms8 += start.elapsed().as_secs_f64() * 1e3;
        }
    }
    let runs = (count * repeats).max(1) as f64;
    println!(
        "{{\"images\": {count}, \"first\": {first}, \"threads\": {threads}, \"repeats\": {repeats}, \
         \"fp32_keypoints\": {n32}, \"int8_keypoints\": {n8}, \
         \"reproduced_within_1px\": {:.4}, \"descriptor_mean_abs_diff\": {:.5}, \
         \"fp32_ms\": {:.2}, \"int8_ms\": {:.2}, \"speedup\": {:.3}}}",
        hit as f64 / n32.max(1) as f64,
        desc_diff / pairs.max(1) as f64,
        ms32 / runs,
        ms8 / runs,
        ms32 / ms8.max(1e-9)
    );
    Ok(())
}

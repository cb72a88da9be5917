//! The paper's greedy selection of FREAK's descriptor pairs, run offline by
//! `examples/train_freak_pairs.rs` to generate [`super::freak_pairs`].
//!
//! Alahi et al. (2012, §4.3): describe many keypoints with all 903 field comparisons, order
//! the comparisons by how close their mean is to 0.5 (most informative first), keep the best
//! and add, in that order, each comparison whose |correlation| with every kept one is below a
//! threshold; if fewer than 512 are kept, raise the threshold and start again. Here the
//! threshold starts at 0.2 and rises by 0.05; ties in the order go to the lower pair index,
//! so the result is a pure function of the training bits.

use crate::FeaturesError;

/// Comparison bits of many keypoints, stored per comparison (column) as a bitset over rows.
#[derive(Debug, Clone)]
pub struct BitColumns {
    rows: usize,
    columns: Vec<Vec<u64>>,
}

impl BitColumns {
    /// `columns` empty columns.
    pub fn new(columns: usize) -> Self {
        Self {
            rows: 0,
            columns: vec![Vec::new(); columns],
        }
    }

    /// Appends one row: `bit(c)` for every column `c`.
    pub fn push_row(&mut self, bit: impl Fn(usize) -> bool) {
        let (word, mask) = (self.rows / 64, 1u64 << (self.rows % 64));
        for (c, col) in self.columns.iter_mut().enumerate() {
            if col.len() <= word {
                col.push(0);
            }
            if bit(c) {
                col[word] |= mask;
            }
        }
        self.rows += 1;
    }

    /// Rows appended so far.
    pub fn rows(&self) -> usize {
        self.rows
    }

    fn ones(&self, c: usize) -> u32 {
        self.columns[c].iter().map(|w| w.count_ones()).sum()
    }

    fn both(&self, a: usize, b: usize) -> u32 {
        let (a, b) = (&self.columns[a], &self.columns[b]);
        a.iter().zip(b).map(|(x, y)| (x & y).count_ones()).sum()
    }
}

/// Pearson correlation of two binary columns with means `ma`, `mb`.
fn correlation(bits: &BitColumns, a: usize, b: usize, ma: f64, mb: f64) -> f64 {
    let n = bits.rows as f64;
    let p11 = f64::from(bits.both(a, b)) / n;
    (p11 - ma * mb) / (ma * (1.0 - ma) * mb * (1.0 - mb)).sqrt()
}

/// Indices of `n` columns chosen greedily (see the module docs).
pub fn select(bits: &BitColumns, n: usize) -> Result<Vec<usize>, FeaturesError> {
    let rows = bits.rows as f64;
    let means: Vec<f64> = (0..bits.columns.len())
        .map(|c| f64::from(bits.ones(c)) / rows.max(1.0))
        .collect();
    let mut order: Vec<usize> = (0..means.len())
        .filter(|&c| means[c] > 0.0 && means[c] < 1.0)
        .collect();
    order.sort_by(|&a, &b| {
        let (da, db) = ((means[a] - 0.5).abs(), (means[b] - 0.5).abs());
        da.total_cmp(&db).then(a.cmp(&b))
    });
    if order.len() < n {
        return Err(FeaturesError::BadInput(format!(
            "{} informative comparisons over {} keypoints; {n} needed",
            order.len(),
            bits.rows
        )));
    }
    let mut threshold = 0.2;
    loop {
        let mut kept: Vec<usize> = Vec::with_capacity(n);
        for &c in &order {
            let ok = kept
                .iter()
                .all(|&k| correlation(bits, c, k, means[c], means[k]).abs() < threshold);
            if ok {
                kept.push(c);
                if kept.len() == n {
                    return Ok(kept);
                }
            }
        }
        threshold += 0.05;
    }
}

/// The generated Rust source of the pair table (`pairs` as `(a, b)` field indices).
pub fn render_table(pairs: &[(u8, u8)], keypoints: usize, command: &str) -> String {
    let mut s = String::new();
    s.push_str("//! FREAK's 512 descriptor pairs, GENERATED — do not edit.\n//!\n");
    s.push_str(&format!(
        "//! Selected by the greedy training of `pairs_training` from {keypoints} keypoints\n"
    ));
    s.push_str("//! of the Ouster sample recordings. Regenerate with:\n//!\n");
    s.push_str(&format!("//! ```text\n//! {command}\n//! ```\n\n"));
    s.push_str(
        "/// `(a, b)`: bit `k` is 1 when field `a` of pair `k` is brighter than field `b`.\n",
    );
    // Eight pairs a line, kept as written (so regenerating is byte-identical).
    s.push_str("#[rustfmt::skip]\n");
    s.push_str(&format!(
        "pub const SELECTED_PAIRS: [(u8, u8); {}] = [\n",
        pairs.len()
    ));
    for chunk in pairs.chunks(8) {
        let items: Vec<String> = chunk.iter().map(|(a, b)| format!("({a}, {b})")).collect();
        s.push_str(&format!("    {},\n", items.join(", ")));
    }
    s.push_str("];\n");
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keeps_balanced_uncorrelated_columns_first() {
        // Column 0: balanced; 1: copy of 0 (correlated); 2: balanced, independent of 0;
        // 3: unbalanced; 4: constant (uninformative).
        let mut bits = BitColumns::new(5);
        for r in 0..64usize {
            let (a, b) = (r % 2 == 0, (r / 2) % 2 == 0);
            let row = [a, a, b, r % 8 == 0, true];
            bits.push_row(|c| row[c]);
        }
        assert_eq!(bits.rows(), 64);
        assert_eq!(select(&bits, 2).unwrap(), vec![0, 2]);
        assert_eq!(select(&bits, 3).unwrap(), vec![0, 2, 3]);
        // The copy comes in only once the threshold has risen to 1.
        assert_eq!(select(&bits, 4).unwrap().len(), 4);
        assert!(select(&bits, 5).is_err());
    }

    #[test]
    fn renders_a_compilable_table() {
        let s = render_table(&[(1, 0), (2, 1)], 10, "cargo run");
        assert!(s.contains("#[rustfmt::skip]\npub const SELECTED_PAIRS: [(u8, u8); 2] = [\n    (1, 0), (2, 1),\n];"));
    }
}

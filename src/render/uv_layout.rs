//! A mesh's UV layout against a map: where the triangles fall in texture
//! space, a preview of the map with the layout drawn over it (the Maps
//! window), and whether the map lines up with the layout as it is or
//! mirrored in V.
//!
//! The V test rests on one property of baked and painted maps: the outline
//! of each UV island is drawn in the map, because inside it is the painted
//! or scanned surface and outside a fill (a flat colour, or padding
//! smeared out from the edge), and the two rarely match. So where the map
//! lines up with the layout, its edges (the gradient of its luminance)
//! are strong along the islands' outlines; upside down they fall
//! elsewhere. The test measures the map's mean gradient along the outlines
//! against its mean everywhere, in both orientations, and speaks only when
//! one is clearly higher: a layout without outlines in the map (islands
//! padded with their own colour), or one nearly symmetric in V, cannot
//! tell, and it says so.

use super::textures::TextureImage;

/// Cells per side of the grid the layout and the map are compared on.
pub const GRID: usize = 128;

/// A map's agreement with a UV layout, as it is and mirrored in V: the
/// map's mean luminance gradient on the islands' outlines over its mean
/// gradient everywhere (1 = the outlines are not drawn in the map).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FlipEvidence {
    /// With the map as it is.
    pub as_is: f64,
    /// With the map mirrored in V (what flip V would give).
    pub flipped: f64,
    /// The fraction of grid cells on an outline.
    pub outline: f64,
}

/// What [`FlipEvidence`] says about the map.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FlipVerdict {
    /// The map lines up with the layout as it is.
    Aligned,
    /// The map lines up with the layout mirrored in V: flip V.
    Flip,
    /// Neither orientation is clearly better.
    Unclear,
}

/// One orientation's outline contrast must exceed the other's by this
/// factor to count.
const RATIO: f64 = 1.3;
/// ... and be at least this (outlines not much weaker than the map's
/// typical gradient): the scan's normal map, whose islands are padded
/// with flat normals, reaches 0.88 the right way up and 0.57 upside down.
const FLOOR: f64 = 0.75;
/// Too few outline cells (fraction of the grid) to judge.
const MIN_OUTLINE: f64 = 0.005;

impl FlipEvidence {
    /// Which orientation the evidence favours.
    pub fn verdict(&self) -> FlipVerdict {
        if self.outline < MIN_OUTLINE {
            FlipVerdict::Unclear
        } else if self.flipped > RATIO * self.as_is && self.flipped >= FLOOR {
            FlipVerdict::Flip
        } else if self.as_is > RATIO * self.flipped && self.as_is >= FLOOR {
            FlipVerdict::Aligned
        } else {
            FlipVerdict::Unclear
        }
    }
}

/// The fraction of each of `n`×`n` cells of texture space (row 0 at v = 0,
/// the top, as [`TextureImage`] stores texels) that the triangles cover,
/// sampled at 4×4 points a cell. UVs wrap (a UV of 1.25 samples 0.25,
/// as a repeating sampler does).
pub fn coverage(uvs: &[[f32; 2]], indices: &[u32], n: usize) -> Vec<f32> {
    const SUB: usize = 4;
    let m = n * SUB;
    let mut hit = vec![false; m * m];
    let wrap = |x: f32| x - x.floor();
    for t in indices.chunks_exact(3) {
        let p: Vec<[f32; 2]> = t
            .iter()
            .filter_map(|&i| uvs.get(i as usize))
            .map(|uv| [uv[0] * m as f32, uv[1] * m as f32])
            .collect();
        if p.len() != 3 || p.iter().flatten().any(|x| !x.is_finite()) {
            continue;
        }
        let (x0, x1) = (
            p[0][0].min(p[1][0]).min(p[2][0]),
            p[0][0].max(p[1][0]).max(p[2][0]),
        );
        let (y0, y1) = (
            p[0][1].min(p[1][1]).min(p[2][1]),
            p[0][1].max(p[1][1]).max(p[2][1]),
        );
        // A triangle wider than the texture is a seam artefact: skip it.
        if x1 - x0 > m as f32 || y1 - y0 > m as f32 {
            continue;
        }
        let area =
            (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]);
        let mut mark = |x: f32, y: f32| {
            let i = (wrap(x / m as f32) * m as f32) as usize % m;
            let j = (wrap(y / m as f32) * m as f32) as usize % m;
            hit[j * m + i] = true;
        };
        // Vertices and centroid always count: a triangle smaller than a
        // sample point still covers where it is.
        for q in &p {
            mark(q[0], q[1]);
        }
        mark(
            (p[0][0] + p[1][0] + p[2][0]) / 3.0,
            (p[0][1] + p[1][1] + p[2][1]) / 3.0,
        );
        if area.abs() < 1e-12 {
            continue;
        }
        for y in (y0.floor() as i64)..=(y1.ceil() as i64) {
            for x in (x0.floor() as i64)..=(x1.ceil() as i64) {
                let (cx, cy) = (x as f32 + 0.5, y as f32 + 0.5);
                let e = |a: [f32; 2], b: [f32; 2]| {
                    (b[0] - a[0]) * (cy - a[1]) - (cx - a[0]) * (b[1] - a[1])
                };
                let (w0, w1, w2) = (e(p[1], p[2]), e(p[2], p[0]), e(p[0], p[1]));
                let inside = if area > 0.0 {
                    w0 >= 0.0 && w1 >= 0.0 && w2 >= 0.0
                } else {
                    w0 <= 0.0 && w1 <= 0.0 && w2 <= 0.0
                };
                if inside {
                    mark(cx, cy);
                }
            }
        }
    }
    let mut cells = vec![0.0f32; n * n];
    for j in 0..m {
        for i in 0..m {
            if hit[j * m + i] {
                cells[(j / SUB) * n + i / SUB] += 1.0 / (SUB * SUB) as f32;
            }
        }
    }
    cells
}

/// The map's luminance (Rec. 709 weights on the stored values; a
/// one-channel map as it is), averaged over each of `n`×`n` cells, row 0
/// at the top.
pub fn cell_luminance(map: &TextureImage, n: usize) -> Vec<f32> {
    let (w, h, c) = (
        map.width as usize,
        map.height as usize,
        map.channels as usize,
    );
    if w == 0 || h == 0 || c == 0 || map.texels.len() < w * h * c {
        return vec![0.0; n * n];
    }
    let mut sum = vec![0.0f64; n * n];
    let mut count = vec![0u32; n * n];
    for y in 0..h {
        let j = y * n / h;
        for x in 0..w {
            let t = &map.texels[(y * w + x) * c..];
            let l = if c >= 3 {
                0.2126 * t[0] as f64 + 0.7152 * t[1] as f64 + 0.0722 * t[2] as f64
            } else {
                t[0] as f64
            };
            sum[j * n + x * n / w] += l;
            count[j * n + x * n / w] += 1;
        }
    }
    sum.iter()
        .zip(&count)
        .map(|(&s, &c)| if c == 0 { 0.0 } else { (s / c as f64) as f32 })
        .collect()
}

/// The gradient magnitude of an `n`×`n` grid (central differences,
/// one-sided at the borders).
fn gradient(l: &[f32], n: usize) -> Vec<f32> {
    let at = |i: usize, j: usize| l[j * n + i];
    (0..n * n)
        .map(|k| {
            let (i, j) = (k % n, k / n);
            let gx = at((i + 1).min(n - 1), j) - at(i.saturating_sub(1), j);
            let gy = at(i, (j + 1).min(n - 1)) - at(i, j.saturating_sub(1));
            (gx * gx + gy * gy).sqrt()
        })
        .collect()
}

/// Cells on an island's outline: covered with an empty 4-neighbour.
fn outline(cover: &[f32], n: usize) -> Vec<bool> {
    (0..n * n)
        .map(|k| {
            let (i, j) = (k % n, k / n);
            cover[k] > 0.0
                && [
                    (i.wrapping_sub(1), j),
                    (i + 1, j),
                    (i, j.wrapping_sub(1)),
                    (i, j + 1),
                ]
                .iter()
                .any(|&(a, b)| a < n && b < n && cover[b * n + a] == 0.0)
        })
        .collect()
}

/// How well `map` lines up with the layout, as it is and mirrored in V.
/// `map` is as the mesh would sample it (any flip the artist set already
/// applied): `Flip` then means "flip it (again)".
pub fn flip_evidence(uvs: &[[f32; 2]], indices: &[u32], map: &TextureImage) -> FlipEvidence {
    let cover = coverage(uvs, indices, GRID);
    let edge = outline(&cover, GRID);
    let g = gradient(&cell_luminance(map, GRID), GRID);
    let mean_all = g.iter().map(|&x| x as f64).sum::<f64>() / g.len() as f64;
    // Mirroring the map in V puts cell row j where row GRID − 1 − j was.
    let mirrored = |k: usize| (GRID - 1 - k / GRID) * GRID + k % GRID;
    let on_outline = |f: &dyn Fn(usize) -> usize| {
        let (sum, count) = (0..GRID * GRID)
            .filter(|&k| edge[k])
            .fold((0.0f64, 0usize), |(s, c), k| (s + g[f(k)] as f64, c + 1));
        if count == 0 || mean_all <= 0.0 {
            0.0
        } else {
            sum / count as f64 / mean_all
        }
    };
    FlipEvidence {
        as_is: on_outline(&|k| k),
        flipped: on_outline(&mirrored),
        outline: edge.iter().filter(|&&e| e).count() as f64 / (GRID * GRID) as f64,
    }
}

/// A UV quantised to 1/65536 (a side's end, to find shared sides).
type UvKey = (i64, i64);

/// A `size`×`size` RGBA preview: the map as the mesh samples it, darkened
/// where no triangle samples it, with the UV islands' outlines drawn over
/// it in yellow.
pub fn preview(uvs: &[[f32; 2]], indices: &[u32], map: &TextureImage, size: usize) -> Vec<u8> {
    let (w, h, c) = (
        map.width as usize,
        map.height as usize,
        map.channels as usize,
    );
    let mut px = vec![0u8; size * size * 4];
    let ok = w > 0 && h > 0 && c > 0 && map.texels.len() >= w * h * c;
    for y in 0..size {
        for x in 0..size {
            let o = (y * size + x) * 4;
            if ok {
                let t = &map.texels[((y * h / size) * w + x * w / size) * c..];
                let rgb = if c >= 3 {
                    [t[0], t[1], t[2]]
                } else {
                    [t[0]; 3]
                };
                px[o..o + 3].copy_from_slice(&rgb);
            }
            px[o + 3] = 255;
        }
    }
    let cover = coverage(uvs, indices, size);
    for (k, &f) in cover.iter().enumerate() {
        if f == 0.0 {
            for v in &mut px[k * 4..k * 4 + 3] {
                *v /= 3;
            }
        }
    }
    // The islands' outlines: triangle sides that no other triangle shares
    // in UV space (keyed by their ends' UVs, so vertices split only for
    // normals do not draw seams), skipping sides that wrap.
    let key = |uv: &[f32; 2]| ((uv[0] * 65536.0) as i64, (uv[1] * 65536.0) as i64);
    let mut sides: std::collections::HashMap<(UvKey, UvKey), (u32, [f32; 4])> =
        std::collections::HashMap::new();
    for t in indices.chunks_exact(3) {
        for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
            let (Some(a), Some(b)) = (uvs.get(a as usize), uvs.get(b as usize)) else {
                continue;
            };
            if !a.iter().chain(b).all(|x| x.is_finite()) {
                continue;
            }
            let (ka, kb) = (key(a), key(b));
            let k = if ka <= kb { (ka, kb) } else { (kb, ka) };
            sides.entry(k).or_insert((0, [a[0], a[1], b[0], b[1]])).0 += 1;
        }
    }
    let s = size as f32;
    let mut plot = |x: i64, y: i64| {
        if (0..size as i64).contains(&x) && (0..size as i64).contains(&y) {
            let o = (y as usize * size + x as usize) * 4;
            px[o..o + 3].copy_from_slice(&[255, 220, 60]);
        }
    };
    for (count, [ax, ay, bx, by]) in sides.into_values() {
        if count != 1 {
            continue;
        }
        let (ax, ay, bx, by) = (ax * s, ay * s, bx * s, by * s);
        let steps = (bx - ax).abs().max((by - ay).abs()).ceil();
        if steps > s {
            continue;
        }
        let steps = steps.max(1.0) as i64;
        for k in 0..=steps {
            let f = k as f32 / steps as f32;
            plot((ax + f * (bx - ax)) as i64, (ay + f * (by - ay)) as i64);
        }
    }
    px
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two triangles covering the unit square cover every cell; one
    /// covering the top half (v < 0.5) covers the top rows only.
    #[test]
    fn coverage_of_squares_and_halves() {
        let square = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let full = coverage(&square, &[0, 1, 2, 0, 2, 3], 8);
        assert!(full.iter().all(|&f| f == 1.0), "{full:?}");
        // 0.49, not 0.5: a vertex marks the sample cell it lies in.
        let top = [[0.0, 0.0], [1.0, 0.0], [1.0, 0.49], [0.0, 0.49]];
        let half = coverage(&top, &[0, 1, 2, 0, 2, 3], 8);
        for j in 0..8 {
            for i in 0..8 {
                let want = if j < 4 { 1.0 } else { 0.0 };
                assert_eq!(half[j * 8 + i], want, "cell {i},{j}");
            }
        }
    }

    /// A map with a checker where the layout is (a band at the top) and
    /// a flat grey fill elsewhere lines up as it is; mirrored, it asks for
    /// flip V; a layout covering everything cannot tell.
    #[test]
    fn a_map_upside_down_is_told_apart() {
        let n = 128;
        let island = [[0.1, 0.1], [0.9, 0.1], [0.9, 0.45], [0.1, 0.45]];
        let mut texels = vec![0u8; n * n];
        for y in 0..n {
            for x in 0..n {
                let (u, v) = ((x as f32 + 0.5) / n as f32, (y as f32 + 0.5) / n as f32);
                let inside = (0.1..0.9).contains(&u) && (0.1..0.45).contains(&v);
                texels[y * n + x] = if inside {
                    if (x / 4 + y / 4) % 2 == 0 {
                        30
                    } else {
                        220
                    }
                } else {
                    128
                };
            }
        }
        let mut map = TextureImage {
            width: n as u32,
            height: n as u32,
            channels: 1,
            texels,
        };
        let idx = [0, 1, 2, 0, 2, 3];
        let e = flip_evidence(&island, &idx, &map);
        assert_eq!(e.verdict(), FlipVerdict::Aligned, "{e:?}");
        map.flip_v();
        let e = flip_evidence(&island, &idx, &map);
        assert_eq!(e.verdict(), FlipVerdict::Flip, "{e:?}");
        let all = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let e = flip_evidence(&all, &idx, &map);
        assert_eq!(e.verdict(), FlipVerdict::Unclear, "{e:?}");
    }
}

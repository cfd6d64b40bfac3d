//! How a side-by-side half frames the head: the camera steps back for a
//! half too narrow for the head's width.

/// How much farther the camera stands for a side-by-side half of `size`
/// (w, h): 1 for a half at least [`FRAMED_ASPECT`] wide, more for a
/// narrower one so that the width the head needs still fits — the
/// framing distance frames the head by height, and a half 242 px wide at
/// 1280×720 cut off an eye and the ears. Tested by
/// `side_by_side_halves_zoom_out_to_keep_the_head_whole`.
pub fn side_by_side_zoom_out((w, h): (u32, u32)) -> f32 {
    if w == 0 || h == 0 {
        return 1.0;
    }
    let aspect = w as f32 / h as f32;
    (FRAMED_ASPECT / aspect).max(1.0)
}

/// The narrowest aspect (width / height) that shows the whole head at its
/// framing distance: the default head is 0.78 as wide as it is tall with
/// the neck (`Mesh::head_size`), and a little room either side.
pub(super) const FRAMED_ASPECT: f32 = 0.85;

#[cfg(test)]
mod side_by_side_tests {
    use super::*;

    /// At 1280×720 the viewport is 484×585 and each half 242×585 (aspect
    /// 0.41): the camera stands 0.85/0.41 = 2.05× farther; a half already
    /// wider than 0.85 keeps the view as it is.
    #[test]
    fn side_by_side_halves_zoom_out_to_keep_the_head_whole() {
        assert!((side_by_side_zoom_out((242, 585)) - 0.85 * 585.0 / 242.0).abs() < 1e-5);
        assert_eq!(side_by_side_zoom_out((700, 600)), 1.0);
        assert_eq!(side_by_side_zoom_out((0, 0)), 1.0);
    }
}

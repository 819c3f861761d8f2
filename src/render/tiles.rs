//! The image split into square tiles, the unit of parallel work.

/// Tile edge in pixels: 16×16 = 256 camera rays per batch, 32 packets of 8.
pub const TILE_SIZE: u32 = 16;

/// A rectangle of pixels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Tile {
    /// Left column.
    pub x0: u32,
    /// Top row.
    pub y0: u32,
    /// Width in pixels (≤ [`TILE_SIZE`]).
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
}

impl Tile {
    /// Number of pixels.
    pub fn pixel_count(&self) -> usize {
        self.width as usize * self.height as usize
    }

    /// Image coordinates of the tile's pixel at row-major index `local`.
    #[inline]
    pub fn pixel(&self, local: usize) -> (u32, u32) {
        let local = local as u32;
        (self.x0 + local % self.width, self.y0 + local / self.width)
    }
}

/// The tiles covering a `width × height` image, row by row; edge tiles are cropped.
pub fn tiles(width: u32, height: u32, size: u32) -> Vec<Tile> {
    let size = size.max(1);
    let mut out = Vec::new();
    for y0 in (0..height).step_by(size as usize) {
        for x0 in (0..width).step_by(size as usize) {
            out.push(Tile {
                x0,
                y0,
                width: size.min(width - x0),
                height: size.min(height - y0),
            });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tiles_cover_every_pixel_once() {
        let (w, h) = (37, 20);
        let mut covered = vec![0u8; (w * h) as usize];
        for tile in tiles(w, h, TILE_SIZE) {
            for i in 0..tile.pixel_count() {
                let (x, y) = tile.pixel(i);
                covered[(y * w + x) as usize] += 1;
            }
        }
        assert!(covered.iter().all(|&c| c == 1));
    }
}

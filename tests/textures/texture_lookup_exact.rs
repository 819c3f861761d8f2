//! The fused texture lookups (one storage-format dispatch per lookup, floors and wraps without
//! library calls or divisions, see `texture::filter` and `texture::image`) against a plain
//! re-statement of the filters as they were before that change: a probe loop calling a
//! trilinear lookup per probe, each level read texel by texel through the general wrap with
//! `f64::floor`. Every lookup must be bit for bit the same (`to_bits` of every channel) over
//! random points and footprints, from magnified to far minified, grazing, non-finite, far from
//! the origin (±10⁶ and beyond 2⁵² texels), on power-of-two and odd sizes, under every wrap
//! mode, magnification filter and storage layout (8-bit grey / RGB / RGBA sRGB, 16-bit grey
//! alpha, f32). That is what keeps the recorded image hashes (`tests/render/image_hashes.rs`)
//! unchanged.

use crate::support::SplitMix as Rng;
use glam::{DVec2, Vec2, Vec4};
use glint::scene::texels::Texels;
use glint::scene::texture_decode::ColorSpace;
use glint::scene::{MagFilter, WrapMode};
use glint::texture::filter::MAX_ANISOTROPY;
use glint::texture::image::{TexelGrid, Wrap};
use glint::texture::{MipMap, TextureFilter, UvFootprint, lookup};

// ---- The reference: the filters as written before the fused lookups. ----

fn split(st: f64) -> (i64, f32) {
    let floor = st.floor();
    (floor as i64, (st - floor) as f32)
}

fn texel_space(uv: Vec2, g: &TexelGrid) -> DVec2 {
    let uv = if uv.is_finite() { uv } else { Vec2::ZERO };
    uv.as_dvec2() * DVec2::new(f64::from(g.width), f64::from(g.height))
}

fn ref_nearest(g: &TexelGrid, uv: Vec2, wrap: Wrap) -> Vec4 {
    let st = texel_space(uv, g);
    g.texel(split(st.x).0, split(st.y).0, wrap)
}

fn ref_bilinear(g: &TexelGrid, uv: Vec2, wrap: Wrap) -> Vec4 {
    let st = texel_space(uv, g) - 0.5;
    let ((x, fx), (y, fy)) = (split(st.x), split(st.y));
    let (x1, y1) = (x.saturating_add(1), y.saturating_add(1));
    let top = g.texel(x, y, wrap).lerp(g.texel(x1, y, wrap), fx);
    let bottom = g.texel(x, y1, wrap).lerp(g.texel(x1, y1, wrap), fx);
    top.lerp(bottom, fy)
}

fn ref_trilinear(mip: &MipMap, uv: Vec2, lod: f32) -> Vec4 {
    let top = (mip.level_count() - 1) as f32;
    if lod <= 0.0 {
        return match mip.mag_filter {
            MagFilter::Nearest => ref_nearest(mip.level(0), uv, mip.wrap),
            MagFilter::Linear => ref_bilinear(mip.level(0), uv, mip.wrap),
        };
    }
    if lod.is_nan() || lod >= top {
        return ref_bilinear(mip.level(mip.level_count() - 1), uv, mip.wrap);
    }
    let l0 = lod.floor();
    let f = lod - l0;
    let l0 = l0 as usize;
    let a = ref_bilinear(mip.level(l0), uv, mip.wrap);
    let b = ref_bilinear(mip.level(l0 + 1), uv, mip.wrap);
    a.lerp(b, f)
}

fn ref_anisotropic(mip: &MipMap, uv: Vec2, footprint: &UvFootprint) -> Vec4 {
    let base = mip.level(0);
    let size = Vec2::new(base.width as f32, base.height as f32);
    let (dx, dy) = (footprint.duv_dx * size, footprint.duv_dy * size);
    let (lx, ly) = (dx.length(), dy.length());
    if !(lx.is_finite() && ly.is_finite()) {
        return ref_trilinear(mip, uv, f32::INFINITY);
    }
    let (major_uv, major, minor) = if lx >= ly {
        (footprint.duv_dx, lx, ly)
    } else {
        (footprint.duv_dy, ly, lx)
    };
    let minor = minor.max(major / MAX_ANISOTROPY);
    if major <= 1.0 || minor <= 0.0 {
        return ref_trilinear(mip, uv, minor.max(major).log2());
    }
    let lod = minor.log2();
    let probes = (major / minor).ceil().clamp(1.0, MAX_ANISOTROPY) as u32;
    if probes == 1 {
        return ref_trilinear(mip, uv, lod);
    }
    let mut sum = Vec4::ZERO;
    for i in 0..probes {
        let offset = (i as f32 + 0.5) / probes as f32 - 0.5;
        sum += ref_trilinear(mip, uv + major_uv * offset, lod);
    }
    sum / probes as f32
}

fn ref_lookup(mip: &MipMap, uv: Vec2, footprint: &UvFootprint, filter: TextureFilter) -> Vec4 {
    match filter {
        TextureFilter::Nearest => ref_nearest(mip.level(0), uv, mip.wrap),
        TextureFilter::Bilinear => ref_bilinear(mip.level(0), uv, mip.wrap),
        TextureFilter::Trilinear => {
            let base = mip.level(0);
            let size = Vec2::new(base.width as f32, base.height as f32);
            let rho = (footprint.duv_dx * size)
                .length()
                .max((footprint.duv_dy * size).length());
            let lod = if rho.is_nan() {
                f32::INFINITY
            } else {
                rho.log2()
            };
            ref_trilinear(mip, uv, lod)
        }
        TextureFilter::Anisotropic => ref_anisotropic(mip, uv, footprint),
        TextureFilter::Bicubic => unreachable!("bicubic is not part of this comparison"),
    }
}

// ---- The inputs. ----

/// `w × h` texels of each layout, random codes.
fn layouts(w: u32, h: u32, rng: &mut Rng) -> Vec<(&'static str, Texels)> {
    let n = (w * h) as usize;
    let mut bytes = |c: usize| (0..n * c).map(|_| rng.next() as u8).collect::<Vec<u8>>();
    let grey = Texels::from_u8(1, ColorSpace::Srgb, bytes(1)).expect("grey");
    let rgb = Texels::from_u8(3, ColorSpace::Srgb, bytes(3)).expect("rgb");
    let rgba = Texels::from_u8(4, ColorSpace::Linear, bytes(4)).expect("rgba");
    let ga16: Vec<u16> = (0..n * 2).map(|_| rng.next() as u16).collect();
    let ga16 = Texels::from_u16(2, ColorSpace::Srgb, ga16).expect("ga16");
    let f32s: Vec<Vec4> = (0..n)
        .map(|_| Vec4::new(rng.unit(), rng.unit() * 4.0, rng.unit(), rng.unit()))
        .collect();
    vec![
        ("u8 grey sRGB", grey),
        ("u8 RGB sRGB", rgb),
        ("u8 RGBA linear", rgba),
        ("u16 grey-alpha sRGB", ga16),
        ("f32 RGBA", Texels::from_linear(f32s)),
    ]
}

/// A random texture coordinate: mostly near [0, 1], some far away, a few beyond 2⁵² texels
/// and non-finite.
fn uv(rng: &mut Rng) -> Vec2 {
    match rng.next() % 16 {
        0 => Vec2::new(rng.signed(1e6), rng.signed(1e6)),
        1 => Vec2::new(rng.signed(1e30), rng.unit()),
        2 => Vec2::new(f32::NAN, rng.unit()),
        3 => Vec2::new(rng.unit(), f32::INFINITY),
        4 => Vec2::new(rng.unit() + 1.0, rng.unit() - 1.0),
        5 => Vec2::new(rng.signed(3.0), rng.signed(3.0)).round(),
        _ => Vec2::new(rng.signed(2.0), rng.signed(2.0)),
    }
}

/// A random footprint: axis lengths from 10⁻⁴ to 10 in uv (magnified to the whole texture),
/// some grazing (up to 10³ : 1), degenerate, or non-finite.
fn footprint(rng: &mut Rng) -> UvFootprint {
    let length = |rng: &mut Rng| 10f32.powf(rng.signed(1.0) * 2.5 - 1.5);
    let dir = |rng: &mut Rng| {
        let a = rng.unit() * std::f32::consts::TAU;
        Vec2::new(a.cos(), a.sin())
    };
    match rng.next() % 12 {
        0 => UvFootprint::default(),
        1 => UvFootprint {
            duv_dx: Vec2::new(f32::NAN, 0.0),
            duv_dy: dir(rng),
        },
        2 => UvFootprint {
            duv_dx: dir(rng) * f32::INFINITY,
            duv_dy: dir(rng) * 1e-3,
        },
        3 => {
            let major = length(rng);
            UvFootprint {
                duv_dx: dir(rng) * major,
                duv_dy: dir(rng) * major * 10f32.powf(-3.0 * rng.unit()),
            }
        }
        _ => UvFootprint {
            duv_dx: dir(rng) * length(rng),
            duv_dy: dir(rng) * length(rng),
        },
    }
}

fn bits(v: Vec4) -> [u32; 4] {
    v.to_array().map(f32::to_bits)
}

#[test]
fn fused_lookups_are_bit_identical_to_the_per_probe_filters() {
    let mut rng = Rng(15);
    let wraps = [
        WrapMode::Repeat,
        WrapMode::MirroredRepeat,
        WrapMode::ClampToEdge,
    ];
    let filters = [
        TextureFilter::Nearest,
        TextureFilter::Bilinear,
        TextureFilter::Trilinear,
        TextureFilter::Anisotropic,
    ];
    let mut compared = 0usize;
    for &(w, h) in &[(64u32, 32u32), (7, 5), (1, 1), (48, 1), (256, 256)] {
        for (name, texels) in layouts(w, h, &mut rng) {
            let base = TexelGrid::new(w, h, texels).expect("size");
            for (k, &s) in wraps.iter().enumerate() {
                let t = wraps[(k + 1) % 3];
                for mag in [MagFilter::Linear, MagFilter::Nearest] {
                    let mip = MipMap::from_grid(base.clone(), Wrap { s, t }, mag);
                    for _ in 0..300 {
                        let (p, f) = (uv(&mut rng), footprint(&mut rng));
                        for filter in filters {
                            let got = lookup(&mip, p, &f, filter);
                            let want = ref_lookup(&mip, p, &f, filter);
                            assert_eq!(
                                bits(got),
                                bits(want),
                                "{name} {w}×{h} wrap {s:?}/{t:?} {mag:?} {filter:?} at {p} \
                                 over {f:?}: {got} against {want}"
                            );
                            compared += 1;
                        }
                    }
                }
            }
        }
    }
    assert_eq!(compared, 5 * 5 * 3 * 2 * 300 * 4);
}

/// The fast wrap paths (inside the grid, a repeating power-of-two side, one period either
/// side of a repeating odd side) against the general Euclidean wrap, through single-texel
/// nearest reads at integer texel centres around and far from the grid.
#[test]
fn nearest_reads_wrap_as_the_general_rule_at_every_integer() {
    for &(w, mode) in &[
        (8u32, WrapMode::Repeat),
        (5, WrapMode::Repeat),
        (5, WrapMode::MirroredRepeat),
        (8, WrapMode::ClampToEdge),
    ] {
        let texels: Vec<Vec4> = (0..w).map(|i| Vec4::splat(i as f32)).collect();
        let grid = TexelGrid::new(w, 1, texels).expect("size");
        let wrap = Wrap { s: mode, t: mode };
        let far = [-1_000_003i64, -(1 << 40) - 3, 1 << 41, 999_999_937];
        for i in (-3 * i64::from(w)..3 * i64::from(w)).chain(far) {
            let centre = Vec2::new((i as f32 + 0.5) / w as f32, 0.5);
            // Far integers lose their fraction in f32; compare at the f32 point itself.
            let got = grid.nearest(centre, wrap);
            assert_eq!(
                bits(got),
                bits(ref_nearest(&grid, centre, wrap)),
                "{mode:?} side {w} at {i}"
            );
        }
    }
}

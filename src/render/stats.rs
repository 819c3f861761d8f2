//! What a render did: rays traced by kind, shadow rays avoided and why, and what the scene did
//! not need.

use super::kernel::KernelFlags;
use crate::scene::SceneFeatures;
use std::ops::AddAssign;
use std::time::Duration;

/// Ray counts of one tile or of a whole render.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RayCounts {
    /// Camera rays traced.
    pub camera: u64,
    /// Shadow rays traced.
    pub shadow: u64,
    /// Mirror reflection rays traced (with the path kernel: every bounce ray).
    pub reflection: u64,
    /// Shadow rays not traced: the light is behind the surface (below the geometric or the
    /// shading horizon) or exactly at the shaded point.
    pub skipped_facing_away: u64,
    /// Shadow rays not traced: the point is outside the spot light's outer cone.
    pub skipped_outside_cone: u64,
    /// Shadow rays not traced: the point is at or beyond the light's range.
    pub skipped_beyond_range: u64,
    /// Rays traced again by the visibility tests: continuations past hits that alpha or
    /// back-face culling rejected, and closest-hit re-checks of blocked shadow rays in
    /// scenes with alpha.
    pub retraced: u64,
}

impl RayCounts {
    /// All rays traced.
    pub fn traced(&self) -> u64 {
        self.camera + self.shadow + self.reflection + self.retraced
    }

    /// All shadow rays avoided.
    pub fn skipped(&self) -> u64 {
        self.skipped_facing_away + self.skipped_outside_cone + self.skipped_beyond_range
    }
}

impl AddAssign for RayCounts {
    fn add_assign(&mut self, o: Self) {
        self.camera += o.camera;
        self.shadow += o.shadow;
        self.reflection += o.reflection;
        self.skipped_facing_away += o.skipped_facing_away;
        self.skipped_outside_cone += o.skipped_outside_cone;
        self.skipped_beyond_range += o.skipped_beyond_range;
        self.retraced += o.retraced;
    }
}

/// Statistics of a finished render.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderStats {
    /// Wall-clock time of the render (tiles only: no scene loading or BVH build).
    pub elapsed: Duration,
    /// Rays by kind.
    pub rays: RayCounts,
    /// What the scene uses.
    pub features: SceneFeatures,
    /// Which work the kernel that ran does.
    pub kernel: KernelFlags,
    /// Bytes of texture texels the render held, MIP chains included.
    pub texture_bytes: u64,
    /// Texels of the textures' base levels (`texture_bytes` / this = bytes per texel).
    pub texture_texels: u64,
    /// The metallic-roughness model the materials used.
    pub brdf: crate::bsdf::BrdfModel,
}

impl RenderStats {
    /// Millions of traced rays per second.
    pub fn mrays_per_second(&self) -> f64 {
        let secs = self.elapsed.as_secs_f64();
        if secs > 0.0 {
            self.rays.traced() as f64 / secs / 1e6
        } else {
            0.0
        }
    }

    /// Per-hit work the kernel left out because the scene does not need it.
    pub fn not_modelled(&self) -> Vec<&'static str> {
        let k = &self.kernel;
        let mut out = Vec::new();
        if !k.textures {
            out.push("no textures: no texcoord interpolation");
        }
        if !k.area_lights {
            out.push("no emitters: no area-light sampling");
        }
        if !k.environment {
            out.push("no environment: no environment sampling");
        }
        if !self.features.layered_materials {
            out.push("no coat, sheen or (diffuse) transmission: metallic-roughness lobes only");
        }
        if !k.vertex_colors {
            out.push("no vertex colours: no colour interpolation");
        }
        if !k.shading_normals {
            out.push("no vertex normals: flat shading normals");
        }
        if !k.normal_maps {
            out.push("no normal maps: no tangent frames");
        }
        if !k.alpha {
            out.push("no alpha: no any-hit tests");
        }
        if !k.cull_back_faces {
            out.push("no single-sided materials: no back-face culling");
        }
        out
    }

    /// The one-line summary `glint render` prints.
    pub fn summary(&self) -> String {
        let r = &self.rays;
        let mut line = format!(
            "rendered in {:.2} s: {} camera + {} shadow + {} {} rays, {:.1} Mrays/s; \
             skipped {} shadow rays ({} facing away, {} outside cone, {} beyond range)",
            self.elapsed.as_secs_f64(),
            r.camera,
            r.shadow,
            r.reflection,
            "bounce",
            self.mrays_per_second(),
            r.skipped(),
            r.skipped_facing_away,
            r.skipped_outside_cone,
            r.skipped_beyond_range,
        );
        if r.retraced > 0 {
            line.push_str(&format!(
                "; {} rays re-traced past alpha cut-outs and culled back faces",
                r.retraced
            ));
        }
        let f = &self.features;
        if f.placed_copies > 0 {
            line.push_str(&format!(
                "; {} triangles drawn from {} stored ({} placed copies, two-level)",
                f.drawn_triangles, f.stored_triangles, f.placed_copies
            ));
        }
        if self.texture_bytes > 0 {
            line.push_str(&format!(
                "; textures {:.1} MiB with MIP maps ({:.2} B/texel)",
                self.texture_bytes as f64 / (1024.0 * 1024.0),
                self.texture_bytes as f64 / self.texture_texels.max(1) as f64
            ));
        }
        line.push_str(match self.brdf {
            crate::bsdf::BrdfModel::Compensated => {
                "; BRDF compensated (energy-conserving multiple-scattering GGX)"
            }
            crate::bsdf::BrdfModel::Spec => "; BRDF spec (glTF Appendix B, single-scatter GGX)",
        });
        let skipped = self.not_modelled();
        if !skipped.is_empty() {
            line.push_str("; ");
            line.push_str(&skipped.join(", "));
        }
        line
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn summary_names_rays_skips_and_what_was_left_out() {
        let features = SceneFeatures {
            point_lights: true,
            mirrors: true,
            ..SceneFeatures::default()
        };
        let stats = RenderStats {
            elapsed: Duration::from_millis(500),
            rays: RayCounts {
                camera: 1_000_000,
                shadow: 400_000,
                reflection: 100_000,
                skipped_facing_away: 7,
                skipped_outside_cone: 0,
                skipped_beyond_range: 0,
                retraced: 0,
            },
            features,
            kernel: KernelFlags::for_scene(&features, super::super::KernelChoice::Specialised),
            texture_bytes: 3 << 20,
            texture_texels: 3 << 18,
            brdf: crate::bsdf::BrdfModel::Spec,
        };
        assert!((stats.mrays_per_second() - 3.0).abs() < 1e-9);
        let line = stats.summary();
        for part in [
            "1000000 camera",
            "400000 shadow",
            "100000 bounce",
            "3.0 Mrays/s",
            "BRDF spec (glTF Appendix B",
            "7 facing away",
            "no textures: no texcoord interpolation",
            "no alpha: no any-hit tests",
            "no single-sided materials: no back-face culling",
            "textures 3.0 MiB with MIP maps (4.00 B/texel)",
            "no normal maps: no tangent frames",
        ] {
            assert!(line.contains(part), "missing '{part}' in: {line}");
        }
        assert!(
            line.contains("no emitters: no area-light sampling"),
            "{line}"
        );
    }
}

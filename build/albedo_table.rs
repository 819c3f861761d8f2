//! The directional albedo of single-scattering GGX for the BSDFs' energy compensation,
//! tabulated at build time so that no render computes it at start-up.

use crate::albedo_quadrature;
use crate::fail;
use std::env;
use std::path::PathBuf;

/// Writes `$OUT_DIR/ggx_albedo_table.rs`: `ALBEDO` (`[E0, E1]` per roughness column and μ
/// row) and `AVERAGE` (`[A0, A1]` per column), as exact f32 bit patterns. The columns are
/// independent, so they are integrated on a few threads and joined in order (the same
/// numbers for any thread count). A table already written from the same sources is kept: the
/// script also reruns for the shim, and the quadrature takes seconds in an unoptimised
/// build script.
pub fn ggx_albedo_table() {
    use albedo_quadrature::{MU_NODES, ROUGHNESS_NODES, column};
    use std::hash::{Hash, Hasher};
    let sources = ["src/bsdf/microfacet.rs", "src/bsdf/albedo_quadrature.rs"];
    let mut hasher = std::collections::hash_map::DefaultHasher::new();
    for source in sources {
        println!("cargo:rerun-if-changed={source}");
        std::fs::read(source)
            .unwrap_or_else(|e| fail(&[format!("glint: cannot read {source}: {e}")]))
            .hash(&mut hasher);
    }
    let stamp = format!("// sources {:016x}\n", hasher.finish());
    let out = PathBuf::from(env::var_os("OUT_DIR").unwrap_or_default()).join("ggx_albedo_table.rs");
    if std::fs::read_to_string(&out).is_ok_and(|old| old.starts_with(&stamp)) {
        return;
    }
    let threads = std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .min(8);
    let columns: Vec<(Vec<[f32; 2]>, [f32; 2])> = std::thread::scope(|scope| {
        let workers: Vec<_> = (0..threads)
            .map(|t| {
                scope.spawn(move || {
                    (t..ROUGHNESS_NODES)
                        .step_by(threads)
                        .map(|j| (j, column(j)))
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        let mut all: Vec<_> = workers
            .into_iter()
            .flat_map(|w| {
                w.join().unwrap_or_else(|_| {
                    fail(&["glint: the albedo table's quadrature panicked".into()])
                })
            })
            .collect();
        all.sort_by_key(|(j, _)| *j);
        all.into_iter().map(|(_, c)| c).collect()
    });
    let bits = |v: [f32; 2]| {
        format!(
            "[f32::from_bits({:#010x}), f32::from_bits({:#010x})]",
            v[0].to_bits(),
            v[1].to_bits()
        )
    };
    let mut text = stamp;
    text.push_str(&format!(
        "/// `[E0, E1]` at `[j * MU_NODES + i]` (roughness node `j`, μ row `i`), from the build script.\n\
         static ALBEDO: [[f32; 2]; {}] = [\n",
        MU_NODES * ROUGHNESS_NODES
    ));
    for (albedo, _) in &columns {
        for &e in albedo {
            text.push_str(&bits(e));
            text.push_str(",\n");
        }
    }
    text.push_str(&format!(
        "];\n/// `[A0, A1]` per roughness node, from the build script.\nstatic AVERAGE: [[f32; 2]; {ROUGHNESS_NODES}] = [\n"
    ));
    for (_, average) in &columns {
        text.push_str(&bits(*average));
        text.push_str(",\n");
    }
    text.push_str("];\n");
    let tmp = out.with_extension("rs.tmp");
    if let Err(e) = std::fs::write(&tmp, text).and_then(|()| std::fs::rename(&tmp, &out)) {
        fail(&[format!("glint: cannot write {}: {e}", out.display())]);
    }
}

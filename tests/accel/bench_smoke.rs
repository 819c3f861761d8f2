#![cfg(feature = "bench")]
//! `bench rays` in quick mode through the library: the report must be complete (every backend,
//! build setting, method, workload, query and thread count), every figure finite and positive,
//! and the answers consistent (occlusion against closest hits, backends against each other,
//! thread counts against each other). Nothing here depends on how fast anything is.

use glam::Vec3;
use glint::accel::BackendKind;
use glint::bench::report::{Query, QueryReport, SceneReport, Workload};
use glint::bench::run::build_variants;
use glint::bench::structure::Method;
use glint::bench::timing::{Rate, Timing};
use glint::bench::{BenchError, BenchScene, RaysConfig, RaysReport, SceneSize, run_rays};
use glint::procedural::OwnedMesh;

/// Quick mode, but always with two thread counts so that scaling is reported even on a
/// one-core machine.
fn config() -> RaysConfig {
    RaysConfig {
        threads: 2,
        ..RaysConfig::quick()
    }
}

fn quick_report() -> RaysReport {
    let scenes = BenchScene::all_builtins(SceneSize::Quick);
    let mut lines = Vec::new();
    let report = run_rays(&scenes, &config(), &mut |line| lines.push(line.to_string())).unwrap();
    assert!(!lines.is_empty(), "no progress reported");
    report
}

fn methods(backend: &str) -> &'static [Method] {
    match backend {
        "embree" => &[Method::Single, Method::Packet8],
        _ => &[Method::Single],
    }
}

fn assert_timing_sane(timing: &Timing, what: &str) {
    assert!(timing.runs >= 1, "{what}: no runs");
    for s in [timing.median_s, timing.min_s, timing.max_s] {
        assert!(s.is_finite() && s > 0.0, "{what}: time {s}");
    }
    assert!(
        timing.min_s <= timing.median_s && timing.median_s <= timing.max_s,
        "{what}"
    );
}

fn assert_rate_sane(rate: &Rate, what: &str) {
    for r in [rate.median, rate.min, rate.max] {
        assert!(r.is_finite() && r > 0.0, "{what}: rate {r}");
    }
    assert!(rate.min <= rate.median && rate.median <= rate.max, "{what}");
}

/// Linux reports every thread's CPU time, so there the CPU figures must be present.
const CPU_TIMES_REPORTED: bool = cfg!(target_os = "linux");

fn assert_cpu_figures_sane(q: &QueryReport, what: &str) {
    if CPU_TIMES_REPORTED {
        assert!(q.cpu_seconds.is_some(), "{what}: no CPU time");
    }
    if let Some(cpu) = &q.cpu_seconds {
        assert_timing_sane(cpu, what);
        assert_rate_sane(&q.mrays_per_cpu_s.unwrap(), what);
        let share = q.cpu_share.unwrap();
        assert!(
            share.is_finite() && share > 0.0,
            "{what}: CPU share {share}"
        );
    }
}

fn check_scene(scene: &SceneReport, config: &RaysConfig) {
    let name = &scene.name;
    assert_eq!(scene.camera_rays, config.camera_ray_count(), "{name}");
    assert_eq!(scene.random_rays, config.random_rays, "{name}");
    // Rays each workload traces: every pixel once, or every random ray once.
    let rays_of = |workload: Workload| match workload {
        Workload::Coherent => config.camera_ray_count(),
        Workload::Incoherent => config.random_rays,
    };
    let backends: Vec<&str> = BackendKind::available().iter().map(|k| k.name()).collect();

    // Every build setting of every backend, each with all four queries.
    let expected_builds: usize = BackendKind::available()
        .iter()
        .map(|&k| build_variants(k).len())
        .sum();
    assert_eq!(scene.builds.len(), expected_builds, "{name}");
    assert_eq!(
        scene.builds.iter().filter(|b| b.is_default).count(),
        backends.len()
    );
    for build in &scene.builds {
        let what = format!(
            "{name} {} {} robust={}",
            build.backend, build.quality, build.robust
        );
        assert_timing_sane(&build.build_s, &what);
        if CPU_TIMES_REPORTED {
            assert_timing_sane(&build.build_cpu_s.unwrap(), &what);
        }
        assert_eq!(build.queries.len(), 4, "{what}");
        for q in &build.queries {
            assert_eq!(q.rays, rays_of(q.workload), "{what}");
            assert_eq!(q.threads, config.threads, "{what}");
            assert_rate_sane(&q.mrays_per_s, &what);
            assert_cpu_figures_sane(q, &what);
        }
    }

    // The full matrix on the default build.
    let expected_queries: usize = backends
        .iter()
        .map(|b| methods(b).len() * 2 * 2 * config.thread_counts().len())
        .sum();
    assert_eq!(scene.queries.len(), expected_queries, "{name}");
    for q in &scene.queries {
        let what = format!("{name} {q:?}");
        assert_eq!(q.rays, rays_of(q.workload), "{what}");
        assert!(q.positives <= q.rays, "{what}");
        assert_timing_sane(&q.seconds, &what);
        assert_rate_sane(&q.mrays_per_s, &what);
        assert_cpu_figures_sane(q, &what);
        // Mrays/s is rays over seconds.
        let implied = q.rays as f64 / q.seconds.median_s * 1e-6;
        assert!(
            (q.mrays_per_s.median / implied - 1.0).abs() < 1e-9,
            "{what}"
        );
        // The answers do not depend on the thread count or, within a backend, on whether the
        // rays went one by one or in packets.
        for other in scene
            .queries
            .iter()
            .filter(|o| o.backend == q.backend && o.workload == q.workload && o.query == q.query)
        {
            assert_eq!(other.positives, q.positives, "{what} vs {other:?}");
        }
    }

    // Occlusion agrees with closest hits, for every backend, method and workload.
    assert_eq!(
        scene.consistency.len(),
        backends.iter().map(|b| methods(b).len() * 2).sum::<usize>()
    );
    for check in &scene.consistency {
        let what = format!("{name} {check:?}");
        assert_eq!(check.rays, rays_of(check.workload), "{what}");
        assert!(check.closest_hits > 0, "{what}: the camera sees nothing");
        assert_eq!(check.occluded, check.closest_hits_within_tfar, "{what}");
        match check.workload {
            // Unbounded camera rays: occluded exactly when there is a closest hit.
            Workload::Coherent => assert_eq!(check.occluded, check.closest_hits, "{what}"),
            // Shadow rays of random length: some hits lie beyond the end.
            Workload::Incoherent => assert!(check.occluded < check.closest_hits, "{what}"),
        }
    }

    // Both backends see the same triangles: their hit counts may differ only by rays that
    // graze an edge, which are rare.
    for workload in Workload::ALL {
        for query in Query::ALL {
            let counts: Vec<usize> = scene
                .queries
                .iter()
                .filter(|q| q.workload == workload && q.query == query)
                .map(|q| q.positives)
                .collect();
            let (lo, hi) = (counts.iter().min().unwrap(), counts.iter().max().unwrap());
            assert!(
                hi - lo <= 2 + rays_of(workload) / 1000,
                "{name} {workload:?} {query:?}: {counts:?}"
            );
        }
    }

    // Derived figures: one ratio per Embree query, one packet gain per single/packet pair,
    // one scaling figure per query at the larger thread count.
    let embree_queries = scene
        .queries
        .iter()
        .filter(|q| q.backend == BackendKind::Embree)
        .count();
    if backends.contains(&"bvh") {
        assert_eq!(scene.embree_over_bvh.len(), embree_queries);
    }
    assert_eq!(scene.packet_gains.len(), embree_queries / 2);
    assert_eq!(
        scene.scaling.len(),
        scene.queries.iter().filter(|q| q.threads > 1).count()
    );
    let derived = scene
        .embree_over_bvh
        .iter()
        .map(|r| r.ratio)
        .chain(scene.packet_gains.iter().map(|g| g.packet8_over_single))
        .chain(
            scene
                .scaling
                .iter()
                .flat_map(|s| [s.scaling.speedup, s.scaling.efficiency]),
        )
        .chain(
            scene
                .embree_over_bvh
                .iter()
                .filter_map(|r| r.ratio_per_cpu_s),
        )
        .chain(
            scene
                .packet_gains
                .iter()
                .filter_map(|g| g.packet8_over_single_per_cpu_s),
        )
        .chain(scene.scaling.iter().filter_map(|s| s.cpu_efficiency));
    for x in derived {
        assert!(x.is_finite() && x > 0.0, "{name}: derived figure {x}");
    }
}

#[test]
fn quick_run_is_complete_and_consistent() {
    let config = config();
    let report = quick_report();
    assert_eq!(report.scenes.len(), 3);
    assert_eq!(report.threads, vec![1, 2]);
    assert_eq!(report.runs, config.runs);
    for scene in &report.scenes {
        check_scene(scene, &config);
    }

    // The JSON carries every figure; the table names every scene and backend.
    let json: serde_json::Value = serde_json::from_str(&report.to_json().unwrap()).unwrap();
    for (scene_json, scene) in json["scenes"]
        .as_array()
        .unwrap()
        .iter()
        .zip(&report.scenes)
    {
        assert_eq!(scene_json["name"], scene.name.as_str());
        assert_eq!(
            scene_json["queries"].as_array().unwrap().len(),
            scene.queries.len()
        );
        assert_eq!(
            scene_json["builds"].as_array().unwrap().len(),
            scene.builds.len()
        );
        let first = &scene_json["queries"][0];
        // serde_json parses floats to within an ulp.
        let median = first["mrays_per_s"]["median"].as_f64().unwrap();
        assert!((median / scene.queries[0].mrays_per_s.median - 1.0).abs() < 1e-12);
    }
    let table = report.to_table();
    for scene in &report.scenes {
        assert!(table.contains(&format!("== {}:", scene.name)), "{table}");
    }
    for backend in BackendKind::available() {
        assert!(table.contains(backend.name()), "{table}");
    }
}

#[test]
fn a_scene_without_triangles_is_refused_by_name() {
    let scene = BenchScene {
        name: "nothing".into(),
        meshes: vec![OwnedMesh::default()],
        camera: None,
    };
    let err = run_rays(&[scene], &config(), &mut |_| {}).unwrap_err();
    assert!(matches!(err, BenchError::EmptyScene { .. }), "{err}");
    assert!(err.to_string().contains("nothing"), "{err}");
}

#[test]
fn invalid_geometry_is_refused_before_any_backend_sees_it() {
    let scene = BenchScene {
        name: "broken".into(),
        meshes: vec![OwnedMesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            indices: vec![[0, 1, 3]],
            instances: Vec::new(),
        }],
        camera: None,
    };
    let err = run_rays(&[scene], &config(), &mut |_| {}).unwrap_err();
    assert!(matches!(err, BenchError::InvalidGeometry { .. }), "{err}");
    let message = err.to_string();
    assert!(
        message.contains("broken") && message.contains("triangle 0"),
        "{message}"
    );
}

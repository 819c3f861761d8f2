//! `glint converge`: writes the CSV and the plot, one curve of rows per setting, and refuses a
//! bad reference with a message naming it.

use glint::accel::BackendKind;
use glint::cli::converge::{ConvergeArgs, run};
use glint::render::{FilterSpec, PixelSampling};

fn args(out: std::path::PathBuf) -> ConvergeArgs {
    ConvergeArgs {
        scene: None,
        reference: None,
        out,
        max_spp: 4,
        reference_spp: 64,
        width: 32,
        height: 18,
        backends: vec![BackendKind::Bvh],
        samplers: vec![PixelSampling::Sobol, PixelSampling::Independent],
        filters: vec![FilterSpec::default()],
        seed: 1,
        threads: 2,
        integrator: glint::render::Integrator::Path,
        asset_root: None,
        env: None,
        denoise: false,
        quiet: true,
    }
}

/// `--env` and `--denoise`: each setting gets a denoised curve beside its own, measured against
/// the same reference (or, in a build without Open Image Denoise, the run fails naming the fix).
#[test]
fn denoise_adds_a_curve_per_setting() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("run");
    let mut a = args(out.clone());
    a.samplers = vec![PixelSampling::Sobol];
    a.env = Some(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/demo-env.hdr"));
    a.denoise = true;
    let result = run(a);
    if !glint::denoise::AVAILABLE {
        let err = result.expect_err("no denoiser in this build");
        assert!(err.to_string().contains("--features denoise"), "{err}");
        return;
    }
    result.expect("converge");
    let csv = std::fs::read_to_string(out.join("converge.csv")).expect("csv");
    let rows: Vec<Vec<&str>> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    let rmse = |setting: &str, spp: &str| -> f64 {
        let row = rows
            .iter()
            .find(|r| r[0] == setting && r[1] == spp)
            .unwrap_or_else(|| panic!("no row {setting} {spp}: {csv}"));
        row[4].parse().expect("rmse")
    };
    assert_eq!(rows.len(), 6, "{csv}");
    // At 1 spp the denoised image is closer to the reference than the noisy one.
    assert!(rmse("bvh sobol box:0.5 denoised", "1") < rmse("bvh sobol box:0.5", "1"));
}

#[test]
fn writes_csv_and_plot_for_each_setting() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("run");
    run(args(out.clone())).expect("converge");
    let csv = std::fs::read_to_string(out.join("converge.csv")).expect("csv");
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("setting,spp,seconds,rays,rmse,rel_mse"));
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    // Two settings × (1, 2, 4) spp.
    assert_eq!(rows.len(), 6, "{csv}");
    for row in &rows {
        assert_eq!(row.len(), 6, "{row:?}");
        let rmse: f64 = row[4].parse().expect("rmse");
        assert!(rmse > 0.0 && rmse.is_finite(), "{row:?}");
    }
    assert!(rows.iter().any(|r| r[0] == "bvh sobol box:0.5"));
    assert!(rows.iter().any(|r| r[0] == "bvh independent box:0.5"));
    let plot = image::open(out.join("converge.png")).expect("plot decodes");
    assert_eq!((plot.width(), plot.height()), glint::converge::PLOT_SIZE);
}

/// Both integrators converge: the error falls from 1 to 4 spp for each.
#[test]
fn both_integrators_are_measured() {
    for integrator in [
        glint::render::Integrator::Path,
        glint::render::Integrator::Direct,
    ] {
        let dir = tempfile::tempdir().expect("temp dir");
        let out = dir.path().join("run");
        let mut a = args(out.clone());
        a.samplers = vec![PixelSampling::Independent];
        a.integrator = integrator;
        run(a).expect("converge");
        let csv = std::fs::read_to_string(out.join("converge.csv")).expect("csv");
        let rmse: Vec<f64> = csv
            .lines()
            .skip(1)
            .map(|l| l.split(',').nth(4).unwrap().parse().unwrap())
            .collect();
        assert_eq!(rmse.len(), 3, "{csv}");
        assert!(rmse[2] < rmse[0], "{integrator}: {csv}");
    }
}

#[test]
fn a_bad_reference_is_named() {
    let dir = tempfile::tempdir().expect("temp dir");
    let bogus = dir.path().join("ref.exr");
    std::fs::write(&bogus, b"not an exr").expect("write");
    let mut a = args(dir.path().join("run"));
    a.reference = Some(bogus.clone());
    let err = run(a).expect_err("bad reference").to_string();
    assert!(err.contains("ref.exr"), "{err}");
}

#![allow(clippy::unwrap_used)]
//! Criterion benchmarks of the numerics (issue budgets in docs/benchmarks.md).

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use scatterlab::model::burley::{sample_radius, sample_radius_halley, Burley};
use scatterlab::model::dipole::{Dipole, Medium};
use scatterlab::model::gaussian::GaussianSum;
use scatterlab::model::jimenez::Jimenez2012;
use scatterlab::model::lut::{Lut, LutLayout};
use scatterlab::model::multipole::{Layer, LayeredMultipole};
use scatterlab::model::separable::SeparableKernel;
use scatterlab::model::RadialProfile;
use std::hint::black_box;
use std::time::Duration;

fn skin() -> Burley {
    Burley::from_scattering_distance([0.91058, 0.338275, 0.2718], [0.7568628, 0.32156864, 0.2])
        .unwrap()
}

fn two_layers() -> [Layer; 2] {
    [
        Layer {
            medium: Medium {
                sigma_a_per_mm: [0.005; 3],
                sigma_s_prime_per_mm: [1.3; 3],
            },
            thickness_mm: Some(6.0),
            eta: 1.4,
        },
        Layer {
            medium: Medium {
                sigma_a_per_mm: [0.01; 3],
                sigma_s_prime_per_mm: [1.0; 3],
            },
            thickness_mm: None,
            eta: 1.4,
        },
    ]
}

fn radii(n: usize, max: f64) -> Vec<f64> {
    (0..n).map(|i| max * i as f64 / (n - 1) as f64).collect()
}

fn profile_evaluation(c: &mut Criterion) {
    let r = radii(1024, 10.0);
    let mut g = c.benchmark_group("profile_eval");
    // Throughput in channel values: 1024 radii × 3 channels.
    g.throughput(Throughput::Elements(3 * 1024));
    let models: Vec<(&str, Box<dyn RadialProfile>)> = vec![
        ("burley", Box::new(skin())),
        ("deon_gaussians", Box::new(GaussianSum::deon_skin())),
        (
            "dipole_skin1",
            Box::new(
                Dipole::new(
                    Medium {
                        sigma_a_per_mm: [0.032, 0.17, 0.48],
                        sigma_s_prime_per_mm: [0.74, 0.88, 1.01],
                    },
                    1.3,
                )
                .unwrap(),
            ),
        ),
    ];
    for (name, p) in &models {
        g.bench_function(BenchmarkId::new("reflectance", name), |b| {
            b.iter(|| {
                r.iter()
                    .map(|&x| p.reflectance(black_box(x))[0])
                    .sum::<f64>()
            })
        });
    }
    g.finish();
}

fn inverse_cdf(c: &mut Criterion) {
    let xi: Vec<f64> = (0..1024).map(|i| (i as f64 + 0.5) / 1024.0).collect();
    let mut g = c.benchmark_group("burley_inverse_cdf");
    g.throughput(Throughput::Elements(1024));
    g.bench_function("closed_form", |b| {
        b.iter(|| {
            xi.iter()
                .map(|&x| sample_radius(black_box(x), 1.3))
                .sum::<f64>()
        })
    });
    g.bench_function("halley", |b| {
        b.iter(|| {
            xi.iter()
                .map(|&x| sample_radius_halley(black_box(x), 1.3))
                .sum::<f64>()
        })
    });
    g.finish();
}

fn kernel_builds(c: &mut Criterion) {
    let mut g = c.benchmark_group("kernel_build");
    let j = Jimenez2012::new([0.48, 0.41, 0.28], [1.0, 0.37, 0.3]).unwrap();
    g.bench_function("jimenez2012_25_taps", |b| {
        b.iter(|| j.kernel(black_box(25)).unwrap())
    });
    let s = skin();
    g.bench_function("preintegrated_burley_7_taps", |b| {
        b.iter(|| SeparableKernel::importance_sampled(&s, black_box(7)).unwrap())
    });
    let d = GaussianSum::deon_skin();
    g.bench_function("preintegrated_deon_7_taps", |b| {
        b.iter(|| SeparableKernel::importance_sampled(&d, black_box(7)).unwrap())
    });
    g.finish();
}

fn lut_bakes(c: &mut Criterion) {
    let mut g = c.benchmark_group("lut_bake");
    g.sample_size(10).measurement_time(Duration::from_secs(8));
    let s = skin();
    g.bench_function("preintegrated_256x256_burley", |b| {
        b.iter(|| Lut::bake(&s, LutLayout::default()).unwrap())
    });
    let d = GaussianSum::deon_skin();
    g.bench_function("preintegrated_256x256_deon", |b| {
        b.iter(|| Lut::bake(&d, LutLayout::default()).unwrap())
    });
    g.finish();
}

fn plot_data(c: &mut Criterion) {
    let r = radii(1024, 10.0);
    let mut g = c.benchmark_group("plot_data_1024_radii");
    let s = skin();
    g.bench_function("burley_R_and_rR", |b| {
        b.iter(|| {
            r.iter()
                .map(|&x| (s.reflectance(x), s.r_reflectance(x)))
                .collect::<Vec<_>>()
        })
    });
    let layered = LayeredMultipole::new(&two_layers(), 1.0, 1.0, 10).unwrap();
    g.bench_function("layered_R_and_rR", |b| {
        b.iter(|| {
            r.iter()
                .map(|&x| (layered.reflectance(x), layered.r_reflectance(x)))
                .collect::<Vec<_>>()
        })
    });
    g.finish();
}

fn multipole(c: &mut Criterion) {
    let mut g = c.benchmark_group("multipole");
    g.sample_size(20);
    let layers = two_layers();
    g.bench_function("two_layer_profile_build", |b| {
        b.iter(|| LayeredMultipole::new(black_box(&layers), 1.0, 1.0, 10).unwrap())
    });
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().warm_up_time(Duration::from_millis(500)).measurement_time(Duration::from_secs(3));
    targets = profile_evaluation, inverse_cdf, kernel_builds, lut_bakes, plot_data, multipole
}
criterion_main!(benches);

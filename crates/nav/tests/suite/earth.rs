//! Earth model against published WGS-84 constants and hand-computed values.

use kestrel_nav::nalgebra::Vector3;
use kestrel_nav::{Ellipsoid, Geodetic};

/// Published WGS-84 derived constants (NIMA TR8350.2, table 3.4).
const GAMMA_E: f64 = 9.780_325_335_9;
const GAMMA_P: f64 = 9.832_184_937_8;
const K: f64 = 0.001_931_852_652_41;
const M: f64 = 0.003_449_786_506_84;
const E2: f64 = 0.006_694_379_990_14;

#[test]
fn derived_constants_match_tr8350() {
    let wgs = Ellipsoid::wgs84();
    let n = wgs.normal_gravity();
    // Published to 12 significant digits: half a unit of the last one.
    assert!((wgs.e2() - E2).abs() < 5e-15);
    assert!((n.gamma_e - GAMMA_E).abs() < 1e-10);
    assert!((n.gamma_p - GAMMA_P).abs() < 1e-10);
    assert!((n.k - K).abs() < 1e-13);
    assert!((n.m - M).abs() < 1e-14);
}

#[test]
fn radii_at_45_and_30_degrees() {
    // R_N = a / √(1 − e² sin²L), R_M = a (1 − e²) / (1 − e² sin²L)^{3/2}.
    let wgs = Ellipsoid::wgs84();
    let l45 = 45f64.to_radians();
    assert!((wgs.prime_vertical_radius(l45) - 6_388_838.290_121).abs() < 1e-5);
    assert!((wgs.meridian_radius(l45) - 6_367_381.815_620).abs() < 1e-5);
    let l30 = 30f64.to_radians();
    assert!((wgs.prime_vertical_radius(l30) - 6_383_480.917_690).abs() < 1e-5);
    assert!((wgs.meridian_radius(l30) - 6_351_377.103_716).abs() < 1e-5);
    // Krasovsky (paper 000's start point, 40.1°N).
    let kr = Ellipsoid::krasovsky();
    let l = 40.1f64.to_radians();
    assert!((kr.e2() - 0.006_693_421_622_966).abs() < 1e-15);
    assert!((kr.prime_vertical_radius(l) - 6_387_119.901_666).abs() < 1e-5);
    assert!((kr.meridian_radius(l) - 6_362_036.027_221).abs() < 1e-5);
}

#[test]
fn normal_gravity_with_height() {
    // Somigliana with the published γ_e, k, e², and the TR8350.2 height series.
    let wgs = Ellipsoid::wgs84();
    let l45 = 45f64.to_radians();
    assert!((wgs.gravity(l45, 0.0) - 9.806_197_769_373).abs() < 1e-10);
    assert!((wgs.gravity(l45, 1000.0) - 9.803_112_943_553).abs() < 1e-10);
    assert!((wgs.gravity(30f64.to_radians(), 500.0) - 9.791_704_138_713).abs() < 1e-10);
    assert!((wgs.gravity(0.0, 0.0) - GAMMA_E).abs() < 1e-10);
    assert!((wgs.gravity(std::f64::consts::FRAC_PI_2, 0.0) - GAMMA_P).abs() < 1e-10);
    let g = wgs.gravity_ned(&Geodetic::new(l45, 1.0, 1000.0));
    assert_eq!(g, Vector3::new(0.0, 0.0, wgs.gravity(l45, 1000.0)));
}

#[test]
fn gravity_derivatives_match_finite_differences() {
    let n = Ellipsoid::wgs84().normal_gravity();
    let (lat, h) = (0.6, 2500.0);
    let (s, c) = f64::sin_cos(lat);
    let (dlat, dh) = n.derivatives(s, c, h);
    let at = |l: f64, h: f64| n.at(l.sin().powi(2), h);
    let dl = 1e-5;
    let fd_lat = (at(lat + dl, h) - at(lat - dl, h)) / (2.0 * dl);
    let fd_h = (at(lat, h + 1.0) - at(lat, h - 1.0)) / 2.0;
    assert!((dlat - fd_lat).abs() < 1e-9 * dlat.abs().max(1.0));
    assert!((dh - fd_h).abs() < 1e-12);
}

#[test]
fn earth_and_transport_rates() {
    let wgs = Ellipsoid::wgs84();
    let l = 30f64.to_radians();
    let w = wgs.earth_rate_ned(l);
    assert!((w.x - 7.292_115e-5 * 0.75f64.sqrt()).abs() < 1e-18);
    assert!((w.z + 7.292_115e-5 * 0.5).abs() < 1e-18);
    let pos = Geodetic::new(l, 0.0, 1000.0);
    let v = Vector3::new(100.0, 50.0, 0.0);
    let r = wgs.transport_rate_ned(&pos, &v);
    let rn = 6_383_480.917_690 + 1000.0;
    let rm = 6_351_377.103_716 + 1000.0;
    assert!((r.x - 50.0 / rn).abs() < 1e-15);
    assert!((r.y + 100.0 / rm).abs() < 1e-15);
    assert!((r.z + 50.0 * l.tan() / rn).abs() < 1e-15);
}

#[test]
fn ecef_round_trips_and_known_points() {
    let wgs = Ellipsoid::wgs84();
    // Equator, Greenwich, 100 m: x = a + 100.
    let x = wgs.to_ecef(&Geodetic::new(0.0, 0.0, 100.0));
    assert!((x - Vector3::new(6_378_237.0, 0.0, 0.0)).norm() < 1e-9);
    for &(lat, lon, h) in &[
        (40.1, 118.6, 100.0),
        (-33.9, -70.7, 2500.0),
        (89.999, 10.0, 0.0),
        (-90.0, 0.0, -50.0),
        (0.0, 180.0, 20_200_000.0),
        (60.0, -1.0, 10_000.0),
    ] {
        let p = Geodetic::from_degrees(lat, lon, h);
        let b = wgs.from_ecef(&wgs.to_ecef(&p));
        assert!((b.lat - p.lat).abs() < 1e-13, "lat at {lat}");
        assert!((b.h - p.h).abs() < 1e-6, "h at {lat}");
        // Compare longitudes on the unit circle (±180° are the same).
        assert!((b.lon - p.lon).sin().abs() < 1e-13 && (b.lon - p.lon).cos() > 0.0);
    }
}

#[test]
fn ned_offset_and_displace() {
    let wgs = Ellipsoid::wgs84();
    let a = Geodetic::from_degrees(34.0, 110.0, 200.0);
    // A small north step: arc length R_M δL to second order.
    let b = Geodetic::new(a.lat + 1e-6, a.lon, a.h);
    let d = wgs.ned_offset(&a, &b);
    let rm = wgs.meridian_radius(a.lat) + a.h;
    assert!((d.x - rm * 1e-6).abs() < 1e-6 && d.y.abs() < 1e-9);
    // Tens of km away and back, exactly.
    let step = Vector3::new(25_000.0, -40_000.0, 150.0);
    let c = wgs.displace(&a, &step);
    assert!((wgs.ned_offset(&a, &c) - step).norm() < 1e-6);
    // Chord below the ellipsoid: a 40 km east step on the surface points up
    // the curvature by about s² / (2 R_N).
    let e = wgs.displace(&a, &Vector3::new(0.0, 40_000.0, 0.0));
    let rn = wgs.prime_vertical_radius(a.lat);
    assert!((e.h - a.h - 40_000f64.powi(2) / (2.0 * rn)).abs() < 0.5);
}

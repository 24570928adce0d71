//! The open GINS text formats: write → read round trips and every class of
//! bad input, each with the message naming file, line and column.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use kestrel_io::gins::{
    degrees_exact, degrees_to_radians, last_time, GnssReader, GnssWriter, ImuReader, ImuRecord,
    ImuWriter, NavReader, NavWriter,
};
use kestrel_io::InputError;
use kestrel_nav::measurement::GnssFix;
use kestrel_nav::nalgebra::Vector3;
use kestrel_nav::{Euler, Geodetic, NavState};

/// A file in the temporary directory with a name unique to this process
/// and call.
fn tmp(name: &str, text: &str) -> PathBuf {
    static N: AtomicUsize = AtomicUsize::new(0);
    let k = N.fetch_add(1, Ordering::Relaxed);
    let p = std::env::temp_dir().join(format!("kestrel-gins-{}-{k}-{name}", std::process::id()));
    std::fs::write(&p, text).unwrap();
    p
}

/// A deterministic spread of awkward values (many digits, tiny, negative).
fn value(k: usize, scale: f64) -> f64 {
    let x = ((k as f64 + 1.0) * 0.618_033_988_749_894_9).fract() - 0.5;
    x * scale * (1.0 + 1e-13 * k as f64)
}

fn imu_error(text: &str) -> (PathBuf, String) {
    let p = tmp("imu.txt", text);
    let e = ImuReader::open(&p)
        .unwrap()
        .find_map(Result::err)
        .expect("an error");
    (p, e.to_string())
}

fn gnss_error(text: &str) -> (PathBuf, String) {
    let p = tmp("gnss.txt", text);
    let e = GnssReader::open(&p)
        .unwrap()
        .find_map(Result::err)
        .expect("an error");
    (p, e.to_string())
}

fn nav_error(text: &str) -> (PathBuf, String) {
    let p = tmp("truth.nav", text);
    let e = NavReader::open(&p)
        .unwrap()
        .find_map(Result::err)
        .expect("an error");
    (p, e.to_string())
}

fn at(p: &Path, rest: &str) -> String {
    format!("{}:{rest}", p.display())
}

const IMU_LAYOUT: &str = "time, Δθ xyz, Δv xyz, optional odometer speed";

#[test]
fn imu_round_trip_is_bit_exact() {
    for odometer in [false, true] {
        let records: Vec<ImuRecord> = (0..500)
            .map(|k| ImuRecord {
                time: 345_600.0 + k as f64 * 0.005,
                dtheta: Vector3::new(value(k, 1e-4), value(k + 1, 3e-6), value(k + 2, 1e-9)),
                dvel: Vector3::new(
                    value(k + 3, 0.1),
                    value(k + 4, 1e-3),
                    -0.049 + value(k, 1e-7),
                ),
                odometer: odometer.then(|| 10.0 + value(k + 5, 1.0)),
                line: 0,
            })
            .collect();
        let mut w = ImuWriter::new(Vec::new());
        w.comment("header").unwrap();
        records.iter().for_each(|r| w.write(r).unwrap());
        let path = tmp(
            "imu.txt",
            std::str::from_utf8(&w.into_inner().unwrap()).unwrap(),
        );
        let back: Vec<ImuRecord> = ImuReader::open(&path)
            .unwrap()
            .map(Result::unwrap)
            .collect();
        assert_eq!(back.len(), records.len());
        for (k, (a, b)) in records.iter().zip(&back).enumerate() {
            assert_eq!(*b, ImuRecord { line: k + 2, ..*a });
        }
    }
}

#[test]
fn gnss_round_trip_is_bit_exact_with_and_without_velocity() {
    for with_velocity in [false, true] {
        let fixes: Vec<GnssFix> = (0..300)
            .map(|k| {
                // Positions as receivers give them: in degrees.
                let pos = Geodetic::from_degrees(
                    30.0 + value(k, 0.1),
                    114.0 + value(k + 1, 0.1),
                    20.0 + value(k + 2, 10.0),
                );
                let std = Vector3::new(0.5 + value(k, 0.1), 0.7, 1.3 + value(k + 3, 0.2));
                if with_velocity {
                    GnssFix::new(
                        k as f64 + 0.1,
                        pos,
                        Vector3::new(value(k, 20.0), 3.0, -0.01),
                    )
                    .with_std(std, Vector3::new(0.05, 0.06 + value(k, 0.01), 0.1))
                } else {
                    let f = GnssFix::position_only(k as f64 + 0.1, pos);
                    f.with_std(std, f.vel_std)
                }
            })
            .collect();
        let mut w = GnssWriter::new(Vec::new());
        fixes.iter().for_each(|f| w.write(f).unwrap());
        let path = tmp(
            "gnss.txt",
            std::str::from_utf8(&w.into_inner().unwrap()).unwrap(),
        );
        let back: Vec<GnssFix> = GnssReader::open(&path)
            .unwrap()
            .map(Result::unwrap)
            .collect();
        assert_eq!(back.len(), fixes.len());
        for (a, b) in fixes.iter().zip(&back) {
            assert!(a == b, "{a:?} != {b:?}");
        }
    }
}

#[test]
fn nav_round_trip_keeps_time_position_velocity_exactly() {
    let states: Vec<NavState> = (0..300)
        .map(|k| {
            NavState::new(
                100.0 + k as f64 * 0.005,
                Geodetic::from_degrees(
                    -34.0 + value(k, 1.0),
                    172.0 + value(k + 1, 1.0),
                    value(k, 500.0),
                ),
                Vector3::new(value(k, 30.0), value(k + 1, 30.0), value(k + 2, 1.0)),
                Euler::new(value(k, 0.2), value(k + 1, 0.2), value(k + 2, 6.0)),
            )
        })
        .collect();
    let mut w = NavWriter::new(Vec::new());
    states.iter().for_each(|s| w.write(2345, s).unwrap());
    let path = tmp(
        "truth.nav",
        std::str::from_utf8(&w.into_inner().unwrap()).unwrap(),
    );
    let back: Vec<_> = NavReader::open(&path)
        .unwrap()
        .map(Result::unwrap)
        .collect();
    assert_eq!(back.len(), states.len());
    for (a, b) in states.iter().zip(&back) {
        assert_eq!(b.week, 2345);
        assert_eq!(
            (b.state.time, b.state.pos, b.state.vel),
            (a.time, a.pos, a.vel)
        );
        // The attitude passes through Euler angles in degrees: a few
        // roundings of ~1e-16 rad each.
        assert!(b.state.att.angle_to(&a.att) < 1e-14);
    }
}

#[test]
fn degrees_written_convert_back_to_the_same_radians() {
    for k in 0..20_000 {
        // Radians that some degree value converts to come back exactly ...
        let rad = degrees_to_radians(value(k, 359.0));
        assert_eq!(degrees_to_radians(degrees_exact(rad)), rad, "{rad}");
        // ... any other within one unit in the last place (about 1 in 10
        // doubles is not the image of any double in degrees).
        let rad = value(k, 3.1);
        let back = degrees_to_radians(degrees_exact(rad));
        assert!(
            back == rad || back == rad.next_up() || back == rad.next_down(),
            "{rad}"
        );
    }
}

#[test]
fn blank_lines_comments_and_trailing_comments_are_ignored() {
    let p = tmp(
        "imu.txt",
        "# header\n\n   \n0.01 0.1 0.2 0.3 4 5 6 # trailing\n\t\n# more\n0.02 0.1 0.2 0.3 4 5 6\n",
    );
    let r: Vec<_> = ImuReader::open(&p).unwrap().map(Result::unwrap).collect();
    assert_eq!(r.iter().map(|r| r.line).collect::<Vec<_>>(), [4, 7]);
    assert_eq!(r[0].dvel, Vector3::new(4.0, 5.0, 6.0));
    assert_eq!(last_time(&p), Some(0.02));
}

#[test]
fn missing_file_is_named() {
    let p = std::env::temp_dir().join(format!("kestrel-gins-{}-absent.txt", std::process::id()));
    let e: InputError = ImuReader::open(&p).unwrap_err();
    assert_eq!(e.file, p);
    assert!(
        e.to_string()
            .starts_with(&format!("{}: cannot open the file: ", p.display())),
        "{e}"
    );
    assert!(GnssReader::open(&p).is_err() && NavReader::open(&p).is_err());
    assert_eq!(last_time(&p), None);
}

#[test]
fn wrong_column_count_names_the_first_missing_or_extra_column() {
    let (p, e) = imu_error("0.01 0 0 0 0 0 0\n0.02 0 0 0 0 0\n");
    assert_eq!(
        e,
        at(
            &p,
            &format!("2:7: expected 7 or 8 columns ({IMU_LAYOUT}), found 6")
        )
    );
    let (p, e) = imu_error("0.01 0 0 0 0 0 0 0 0\n");
    assert_eq!(
        e,
        at(
            &p,
            &format!("1:9: expected 7 or 8 columns ({IMU_LAYOUT}), found 9")
        )
    );
    // A file may have the odometer column or not, but not change.
    let (p, e) = imu_error("0.01 0 0 0 0 0 0 5\n0.02 0 0 0 0 0 0\n");
    assert_eq!(
        e,
        at(
            &p,
            "2:8: expected 8 columns like the first data line, found 7"
        )
    );
    let (p, e) = gnss_error("1 30 114 10 1 1 1 0 0 0 0.1 0.1\n");
    assert_eq!(
        e,
        at(
            &p,
            "1:8: expected 7 or 13 columns (time, lat, lon, h, σ NED, optional velocity NED and \
             its σ), found 12"
        )
    );
    let (p, e) = gnss_error("1 30 114 10 1 1 1\n2 30 114 10 1 1 1 0 0 0 0.1 0.1 0.1\n");
    assert_eq!(
        e,
        at(
            &p,
            "2:8: expected 7 columns like the first data line, found 13"
        )
    );
    let (p, e) = nav_error("0 1 30 114 10 0 0 0 0 0\n");
    assert_eq!(
        e,
        at(
            &p,
            "1:11: expected 11 columns (week, time, lat, lon, h, velocity NED, roll, pitch, \
             yaw), found 10"
        )
    );
}

#[test]
fn non_numeric_field_names_its_column_and_meaning() {
    let (p, e) = imu_error("0.01 0 0 0 0 0 0\n0.02 0 0 1.5e-3x 0 0 0\n");
    assert_eq!(
        e,
        at(&p, "2:4: expected a number (Δθ z, rad), found `1.5e-3x`")
    );
    let (p, e) = gnss_error("1 30 114,5 10 1 1 1\n");
    assert_eq!(
        e,
        at(&p, "1:3: expected a number (longitude, deg), found `114,5`")
    );
    let (p, e) = nav_error("0 1 30 114 10 0 0 0 0 zero 0\n");
    assert_eq!(
        e,
        at(&p, "1:10: expected a number (pitch, deg), found `zero`")
    );
}

#[test]
fn nan_and_infinity_are_refused() {
    let (p, e) = imu_error("0.01 0 0 0 NaN 0 0\n");
    assert_eq!(
        e,
        at(&p, "1:5: expected a finite number (Δv x, m/s), found `NaN`")
    );
    let (p, e) = imu_error("0.01 0 0 0 0 0 0 inf\n");
    assert_eq!(
        e,
        at(
            &p,
            "1:8: expected a finite number (odometer speed, m/s), found `inf`"
        )
    );
    let (p, e) = gnss_error("1 30 114 -infinity 1 1 1\n");
    assert_eq!(
        e,
        at(
            &p,
            "1:4: expected a finite number (height, m), found `-infinity`"
        )
    );
    let (p, e) = nav_error("0 1 30 114 10 nan 0 0 0 0 0\n");
    assert_eq!(
        e,
        at(
            &p,
            "1:6: expected a finite number (velocity north, m/s), found `nan`"
        )
    );
}

#[test]
fn time_going_backwards_or_repeating_is_refused() {
    let (p, e) = imu_error("0.01 0 0 0 0 0 0\n0.02 0 0 0 0 0 0\n0.015 0 0 0 0 0 0\n");
    assert_eq!(
        e,
        at(
            &p,
            "3:1: time does not increase: 0.015 s after 0.02 s at line 2 (expected increasing \
             seconds of week)"
        )
    );
    let (p, e) = imu_error("0.01 0 0 0 0 0 0\n# c\n0.01 0 0 0 0 0 0\n");
    assert_eq!(
        e,
        at(
            &p,
            "3:1: time does not increase: 0.01 s after 0.01 s at line 1 (expected increasing \
             seconds of week)"
        )
    );
    let (p, e) = gnss_error("2 30 114 10 1 1 1\n1 30 114 10 1 1 1\n");
    assert_eq!(
        e,
        at(
            &p,
            "2:1: time does not increase: 1 s after 2 s at line 1 (expected increasing seconds \
             of week)"
        )
    );
    let (p, e) = nav_error("5 1 30 114 10 0 0 0 0 0 0\n4 2 30 114 10 0 0 0 0 0 0\n");
    assert_eq!(
        e,
        at(
            &p,
            "2:2: time does not increase: not after line 1 (expected increasing week and \
             seconds of week)"
        )
    );
}

#[test]
fn gaps_are_read_and_a_week_rollover_continues_the_time() {
    // A lost sample is read (`process` bridges or refuses it by its rule).
    let gap = "0.01 0 0 0 0 0 0\n0.02 0 0 0 0 0 0\n0.04 0 0 0 0 0 0\n";
    assert!(ImuReader::open(&tmp("imu.txt", gap))
        .unwrap()
        .all(|r| r.is_ok()));
    // The end of the week: 604799.99, then 0 — continued as 604800.
    let roll = "604799.99 0 0 0 0 0 0\n0 0 0 0 0 0 0\n0.01 0 0 0 0 0 0\n";
    let times: Vec<f64> = ImuReader::open(&tmp("imu.txt", roll))
        .unwrap()
        .map(|r| r.unwrap().time)
        .collect();
    assert_eq!(times, [604_799.99, 604_800.0, 604_800.01]);
    // Going back less than half a week is still an error.
    let (p, e) = imu_error("300000 0 0 0 0 0 0\n1000 0 0 0 0 0 0\n");
    assert_eq!(
        e,
        at(
            &p,
            "2:1: time does not increase: 1000 s after 300000 s at line 1 (expected increasing \
             seconds of week)"
        )
    );
    // GNSS gaps (outages) are normal.
    let g = tmp("gnss.txt", "1 30 114 10 1 1 1\n200 30 114 10 1 1 1\n");
    assert_eq!(
        GnssReader::open(&g).unwrap().filter(Result::is_ok).count(),
        2
    );
}

#[test]
fn gnss_values_out_of_range_are_refused() {
    let (p, e) = gnss_error("1 30 114 10 1 0 1\n");
    assert_eq!(
        e,
        at(
            &p,
            "1:6: expected a standard deviation in [1e-150, 1e150] (its square must be a normal \
             double), found 0 (σ east, m)"
        )
    );
    let (p, e) = gnss_error("1 30 114 10 1 1 1 0 0 0 0.1 0.1 -0.1\n");
    assert_eq!(
        e,
        at(
            &p,
            "1:13: expected a standard deviation in [1e-150, 1e150] (its square must be a \
             normal double), found -0.1 (σ velocity down, m/s)"
        )
    );
    let (p, e) = gnss_error("1 95 114 10 1 1 1\n");
    assert_eq!(
        e,
        at(
            &p,
            "1:2: expected a latitude in [-89.9, 89.9] deg, found 95"
        )
    );
    // A fix at a pole, where the local-level mechanisation is singular.
    let (p, e) = gnss_error("1 -90 114 10 1 1 1\n");
    assert_eq!(
        e,
        at(
            &p,
            "1:2: expected a latitude in [-89.9, 89.9] deg, found -90"
        )
    );
    let (p, e) = gnss_error("1 30 114 10 1e-200 1 1\n");
    assert_eq!(
        e,
        at(
            &p,
            "1:5: expected a standard deviation in [1e-150, 1e150] (its square must be a normal \
             double), found 1e-200 (σ north, m)"
        )
    );
    let (p, e) = gnss_error("1 30 1e308 10 1 1 1\n");
    assert_eq!(
        e,
        at(
            &p,
            "1:3: expected a longitude in [-180, 360] deg, found 1e308"
        )
    );
    let (p, e) = gnss_error("1 30 114 -1e7 1 1 1\n");
    assert_eq!(
        e,
        at(
            &p,
            "1:4: expected a height in [-12000, 100000] m, found -10000000"
        )
    );
    let (p, e) = gnss_error("1 30 114 10 1 1 1 0 1e30 0 0.1 0.1 0.1\n");
    assert_eq!(
        e,
        at(&p, "1:9: expected a speed in [-1000, 1000] m/s, found 1e30")
    );
    let (p, e) = imu_error("0.01 0 0 0 0 0 0 1e30\n");
    assert_eq!(
        e,
        at(
            &p,
            "1:8: expected an odometer speed in [-200, 200] m/s, found 1e30"
        )
    );
    let (p, e) = nav_error("2300.5 1 30 114 10 0 0 0 0 0 0\n");
    assert_eq!(e, at(&p, "1:1: expected a whole GNSS week, found 2300.5"));
}

#[test]
fn a_reader_stops_after_its_first_error() {
    let p = tmp(
        "imu.txt",
        "0.01 0 0 0 0 0 0\nx 0 0 0 0 0 0\n0.02 0 0 0 0 0 0\n",
    );
    let r: Vec<_> = ImuReader::open(&p).unwrap().collect();
    assert_eq!(r.len(), 2);
    assert!(r[1].is_err());
}

/// The file's bytes as real logs have them: a UTF-8 byte-order mark, CR LF
/// line ends and a Latin-1 comment are read; lines ending in CR only, a
/// line without end (a binary or runaway file) and a non-UTF-8 byte in the
/// data are refused with the line and a precise reason, after reading at
/// most one bounded line.
#[test]
fn line_ends_byte_order_marks_and_stray_bytes() {
    let raw = |name: &str, bytes: &[u8]| {
        let p = tmp(name, "");
        std::fs::write(&p, bytes).unwrap();
        p
    };
    let ok = b"\xEF\xBB\xBF# caf\xE9 (Latin-1 comment)\r\n0.01 0 0 0 0 0 0\r\n0.02 0 0 0 0 0 0\r\n";
    let times: Vec<f64> = ImuReader::open(&raw("imu.txt", ok))
        .unwrap()
        .map(|r| r.unwrap().time)
        .collect();
    assert_eq!(times, [0.01, 0.02]);

    let mut cr = Vec::new();
    for k in 1..=400 {
        cr.extend_from_slice(format!("{} 0 0 0 0 0 0\r", f64::from(k) * 0.01).as_bytes());
    }
    let p = raw("imu.txt", &cr);
    let e = ImuReader::open(&p).unwrap().find_map(Result::err).unwrap();
    assert_eq!(
        e.to_string(),
        at(
            &p,
            "1: line longer than 4096 bytes; the lines seem to end in CR only (classic Mac): \
             convert them to LF or CR LF"
        )
    );

    let p = raw("imu.txt", &vec![0u8; 1 << 20]);
    let mut reader = ImuReader::open(&p).unwrap();
    let e = reader.next().unwrap().unwrap_err();
    assert_eq!(
        e.to_string(),
        at(
            &p,
            "1: line longer than 4096 bytes (is this a text file in the expected format?)"
        )
    );
    assert!(reader.next().is_none(), "the reader stops after the error");

    let p = raw("imu.txt", b"0.01 0 0 \xB5 0 0 0\n");
    let e = ImuReader::open(&p).unwrap().find_map(Result::err).unwrap();
    assert_eq!(
        e.to_string(),
        at(
            &p,
            "1:4: byte 0xB5 at byte 10 of the line is not UTF-8 text (only comments after `#` \
             may hold other bytes)"
        )
    );
}

/// Increments no IMU can measure (a column in the wrong unit) and wheel
/// speeds no vehicle drives are refused at their line, with the rate they
/// mean and the bound.
#[test]
fn physically_impossible_imu_and_odometer_values_are_refused() {
    // 1000 rad in one 5 ms increment: 200 000 rad/s.
    let (p, e) = imu_error("0.000 0 0 0 0 0 0\n0.005 1000 0 0 0 0 0\n");
    assert_eq!(
        e,
        at(
            &p,
            "2:2: a rotation of 1000 rad in 0.005 s is 200000 rad/s, beyond any IMU's range \
             (at most 125.7 rad/s, 20 turns a second; is the column in the right unit?)"
        )
    );
    let (p, e) = imu_error("0.000 0 0 0 0 0 0\n0.005 0 0 0 0 0 -100\n");
    assert_eq!(
        e,
        at(
            &p,
            "2:7: a velocity increment of -100 m/s in 0.005 s is 20000 m/s², beyond any IMU's \
             range (at most 9806.65 m/s², 1000 g; is the column in the right unit?)"
        )
    );
    // The bound itself is a rate an IMU can report.
    let p = tmp("imu.txt", "0.000 0 0 0 0 0 0\n0.005 0.6 0 0 0 0 49\n");
    assert!(ImuReader::open(&p).unwrap().all(|r| r.is_ok()));
    // An odometer column at −999 m/s, in the IMU file and on its own.
    let (p, e) = imu_error("0.000 0 0 0 0 0 0 -999\n");
    assert_eq!(
        e,
        at(
            &p,
            "1:8: expected an odometer speed in [-200, 200] m/s, found -999"
        )
    );
    let p = tmp("odometer.txt", "0.0 1.0\n0.1 -999\n");
    let e = kestrel_io::gins::OdometerReader::open(&p)
        .unwrap()
        .find_map(Result::err)
        .expect("an error")
        .to_string();
    assert_eq!(
        e,
        at(
            &p,
            "2:2: expected an odometer speed in [-200, 200] m/s, found -999"
        )
    );
}

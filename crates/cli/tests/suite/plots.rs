//! Figures and per-epoch CSV: valid files, the right content, no panic on
//! empty, single-point, NaN or exploding traces.

use std::path::{Path, PathBuf};

use kestrel::nav::nalgebra::Vector3;
use kestrel_app::experiment::{Adaptation, EpochRecord, PositionAxes};
use kestrel_app::output::write_epochs_csv;
use kestrel_cli::plot::{error_figures, error_figures_with, FigureOptions, FilterTrace};
use kestrel_cli::CliError;

/// A fresh directory for one test.
fn out_dir(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("plots")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// `n` records at 10 Hz with errors `scale·sin`, NIS 1 + t mod 5.
fn records(n: usize, scale: f64, adapt: impl Fn(f64) -> Adaptation) -> Vec<EpochRecord> {
    (0..n)
        .map(|i| {
            let t = i as f64 * 0.1;
            let s = scale * (0.05 * t).sin();
            EpochRecord {
                time: t,
                position: Vector3::new(s, -2.0 * s, 0.5 * s),
                velocity: Vector3::new(0.1 * s, 0.2 * s, -0.1 * s),
                attitude: Vector3::new(1e-4 * s, -1e-4 * s, 3e-4 * s),
                adaptation: adapt(t),
                position_nees: None,
            }
        })
        .collect()
}

fn neutral(t: f64) -> Adaptation {
    Adaptation {
        nis: 1.0 + t % 5.0,
        ..Adaptation::default()
    }
}

// --- file checks -------------------------------------------------------

/// CRC-32 (IEEE) as PNG uses it.
fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = 0xFFFF_FFFF_u32;
    for &b in bytes {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = if crc & 1 == 1 {
                (crc >> 1) ^ 0xEDB8_8320
            } else {
                crc >> 1
            };
        }
    }
    !crc
}

/// Checks the PNG signature, every chunk's CRC, IHDR first and IEND last,
/// at least one IDAT; returns (width, height).
fn png_size(path: &Path) -> (u32, u32) {
    let bytes = std::fs::read(path).unwrap();
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "{}", path.display());
    let mut at = 8;
    let mut chunks = Vec::new();
    let mut size = (0, 0);
    while at < bytes.len() {
        let len = u32::from_be_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
        let kind = &bytes[at + 4..at + 8];
        let data = &bytes[at + 8..at + 8 + len];
        let crc = u32::from_be_bytes(bytes[at + 8 + len..at + 12 + len].try_into().unwrap());
        assert_eq!(
            crc,
            crc32(&bytes[at + 4..at + 8 + len]),
            "{}",
            path.display()
        );
        if kind == b"IHDR" {
            size = (
                u32::from_be_bytes(data[0..4].try_into().unwrap()),
                u32::from_be_bytes(data[4..8].try_into().unwrap()),
            );
        }
        chunks.push(kind.to_vec());
        at += 12 + len;
    }
    assert_eq!(at, bytes.len());
    assert_eq!(chunks.first().map(Vec::as_slice), Some(&b"IHDR"[..]));
    assert_eq!(chunks.last().map(Vec::as_slice), Some(&b"IEND"[..]));
    assert!(chunks.iter().any(|c| c == b"IDAT"));
    size
}

/// Checks that the SVG's tags nest properly; returns its text.
fn svg_text(path: &Path) -> String {
    let text = std::fs::read_to_string(path).unwrap();
    let body = text.trim();
    assert!(body.starts_with("<svg"), "{}", path.display());
    assert!(body.ends_with("</svg>"), "{}", path.display());
    let mut open: Vec<&str> = Vec::new();
    let mut rest = body;
    while let Some(i) = rest.find('<') {
        rest = &rest[i + 1..];
        let end = rest.find('>').expect("unclosed tag");
        let tag = &rest[..end];
        if let Some(name) = tag.strip_prefix('/') {
            assert_eq!(open.pop(), Some(name.trim()), "{}", path.display());
        } else if !tag.ends_with('/') && !tag.starts_with('?') && !tag.starts_with('!') {
            open.push(tag.split_whitespace().next().unwrap());
        }
        rest = &rest[end + 1..];
    }
    assert!(open.is_empty(), "unclosed {open:?} in {}", path.display());
    text
}

/// The points of each `<polyline>` of an SVG.
fn polyline_lengths(svg: &str) -> Vec<usize> {
    svg.split("<polyline")
        .skip(1)
        .map(|p| {
            let start = p.find("points=\"").unwrap() + 8;
            let end = start + p[start..].find('"').unwrap();
            p[start..end].split_whitespace().count()
        })
        .collect()
}

fn names(files: &[PathBuf]) -> Vec<String> {
    files
        .iter()
        .map(|f| f.file_name().unwrap().to_string_lossy().into_owned())
        .collect()
}

// --- figures -------------------------------------------------------------

#[test]
fn figures_of_several_filters_are_valid_png_and_svg_with_legend_and_axes() {
    let dir = out_dir("several");
    // One hour at 10 Hz for the baseline: drawn thinned.
    let mut kf = records(36_000, 3.0, neutral);
    kf[100].position.x = f64::NAN;
    let fading = records(600, 1.0, |t| Adaptation {
        fade: 1.0 + (t % 7.0),
        ..neutral(t)
    });
    let fuzzy = records(600, 0.5, |t| Adaptation {
        alpha1: if t > 20.0 { 0.3 } else { 1.0 },
        rejected: t > 30.0 && t < 31.0,
        ..neutral(t)
    });
    let traces = [
        FilterTrace {
            label: "KF",
            records: &kf,
        },
        FilterTrace {
            label: "fading KF",
            records: &fading,
        },
        FilterTrace {
            label: "fuzzy adaptive",
            records: &fuzzy,
        },
        FilterTrace {
            label: "nothing",
            records: &[],
        },
    ];
    let options = FigureOptions {
        nis_dof: Some(3),
        ..FigureOptions::default()
    };
    let files = error_figures_with(
        &dir,
        "Paper 000",
        PositionAxes::EastNorthUp,
        &traces,
        &options,
    )
    .unwrap();
    assert_eq!(
        names(&files),
        [
            "position.png",
            "position.svg",
            "velocity.png",
            "velocity.svg",
            "attitude.png",
            "attitude.svg",
            "adaptation.png",
            "adaptation.svg"
        ]
    );
    for f in &files {
        assert!(f.starts_with(&dir));
        assert!(
            std::fs::metadata(f).unwrap().len() > 1000,
            "{}",
            f.display()
        );
    }
    // Three panels: 120 px header + 3 × 260 px.
    for png in &files[0..6].iter().step_by(2).collect::<Vec<_>>() {
        assert_eq!(png_size(png), (1200, 900), "{}", png.display());
    }
    // λ and α₁ changed, inflation, compression and tr R did not: λ, α₁, NIS.
    assert_eq!(png_size(&files[6]), (1200, 900));

    let position = svg_text(&files[1]);
    for label in [
        "Paper 000: position error",
        "KF",
        "fading KF",
        "fuzzy adaptive",
        "nothing",
    ] {
        assert!(position.contains(label), "{label}");
    }
    for axis in ["east (m)", "north (m)", "up (m)", "time (s)"] {
        assert!(position.contains(axis), "{axis}");
    }
    assert!(!position.contains("off scale"));
    // 36 000 points thinned to at most two per pixel column.
    let lengths = polyline_lengths(&position);
    assert!(lengths.iter().any(|&n| n > 1000), "{lengths:?}");
    assert!(lengths.iter().all(|&n| n <= 2400), "{lengths:?}");

    let velocity = svg_text(&files[3]);
    assert!(velocity.contains("down (m/s)"));
    // Largest attitude error 3e-4 · 3 rad = 3.1′: arcminutes.
    let attitude = svg_text(&files[5]);
    assert!(attitude.contains("north (arcmin)"));
    let adaptation = svg_text(&files[7]);
    for text in [
        "λ (–)",
        "α₁ (–)",
        "NIS (–)",
        "χ² bound, 3 dof, p = 0.99 (11.34)",
    ] {
        assert!(adaptation.contains(text), "{text}");
    }
    assert!(!adaptation.contains("inflation (–)"));
    assert!(!adaptation.contains("compression (–)"));
}

#[test]
fn empty_single_point_and_all_nan_traces_give_valid_files() {
    let dir = out_dir("degenerate");
    let files = error_figures(&dir, "", PositionAxes::NorthEastDown, &[]).unwrap();
    assert_eq!(files.len(), 8);
    assert_eq!(png_size(&files[0]), (1200, 900));
    // No NIS and no adapter: a single "no data" band.
    assert_eq!(png_size(&files[6]), (1200, 380));
    assert!(svg_text(&files[7]).contains("no data"));

    let one = records(1, 1.0, neutral);
    let mut nan = records(5, 1.0, neutral);
    for r in &mut nan {
        r.position = Vector3::repeat(f64::NAN);
        r.velocity = Vector3::repeat(f64::INFINITY);
        r.attitude = Vector3::repeat(f64::NAN);
        r.adaptation.nis = f64::NAN;
        r.adaptation.fade = f64::NAN;
    }
    let traces = [
        FilterTrace {
            label: "one",
            records: &one,
        },
        FilterTrace {
            label: "nan",
            records: &nan,
        },
    ];
    let files = error_figures(&dir, "odd", PositionAxes::NorthEastDown, &traces).unwrap();
    for pair in files.chunks(2) {
        png_size(&pair[0]);
        assert!(svg_text(&pair[1]).contains("nan"));
    }
    // Only the single point's NIS: one band.
    assert_eq!(png_size(&files[6]), (1200, 380));

    // A title too long for the width is shortened, not drawn off the edge.
    let long = "a very long scenario description ".repeat(10);
    let files = error_figures(&dir, &long, PositionAxes::NorthEastDown, &traces).unwrap();
    let svg = svg_text(&files[1]);
    assert!(svg.contains("a very long scenario description a very long"));
    assert!(svg.contains('…') && !svg.contains(&long));
}

#[test]
fn thinning_keeps_each_buckets_extremes_in_time_order() {
    use kestrel_cli::plot::{split_at_gaps, thin};
    // 1000 points, buckets of 100 (10 buckets for 20 points at most).
    let points: Vec<(f64, f64)> = (0..1000)
        .map(|i| (i as f64, ((i * 37) % 101) as f64))
        .collect();
    let t = thin(&points, 20);
    assert_eq!(t.len(), 20);
    assert!(t.windows(2).all(|w| w[0].0 < w[1].0));
    for (k, chunk) in points.chunks(100).enumerate() {
        let lo = chunk.iter().map(|p| p.1).fold(f64::INFINITY, f64::min);
        let hi = chunk.iter().map(|p| p.1).fold(f64::NEG_INFINITY, f64::max);
        let kept: Vec<f64> = t[2 * k..2 * k + 2].iter().map(|p| p.1).collect();
        assert!(
            kept.contains(&lo) && kept.contains(&hi),
            "bucket {k}: {kept:?}"
        );
    }
    // Short series are kept whole; no points, no panic.
    assert_eq!(thin(&points[..5], 20), points[..5].to_vec());
    assert!(thin(&[], 20).is_empty());
    assert_eq!(split_at_gaps(&[]).len(), 1);
    assert_eq!(split_at_gaps(&points).len(), 1);
}

#[test]
fn an_exploding_filter_is_clipped_and_named_with_its_peak() {
    let dir = out_dir("exploding");
    let good = records(300, 1.0, neutral);
    let mut bad = records(300, 1.0, neutral);
    bad[299].position = Vector3::new(2.0e5, 0.0, 0.0);
    let traces = [
        FilterTrace {
            label: "diverged",
            records: &bad,
        },
        FilterTrace {
            label: "fine",
            records: &good,
        },
    ];
    let files = error_figures(&dir, "x", PositionAxes::NorthEastDown, &traces).unwrap();
    let position = svg_text(&files[1]);
    assert!(position.contains("clipped, off scale: diverged (peak 200000)"));
    // The east and down panels are not clipped.
    assert_eq!(position.matches("off scale").count(), 1);
}

#[test]
fn an_unwritable_directory_is_an_error_not_a_panic() {
    let dir = out_dir("unwritable");
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("a-file");
    std::fs::write(&file, "x").unwrap();
    let r = error_figures(&file, "x", PositionAxes::NorthEastDown, &[]);
    assert!(matches!(r, Err(CliError::Io { .. })), "{r:?}");
    let r = write_epochs_csv(&file.join("e.csv"), PositionAxes::NorthEastDown, &[]);
    assert!(matches!(r, Err(CliError::Io { .. })), "{r:?}");
    // A directory where a figure should go: the error names the file.
    std::fs::create_dir_all(dir.join("velocity.png")).unwrap();
    let r = error_figures(&dir, "x", PositionAxes::NorthEastDown, &[]);
    let message = r.unwrap_err().to_string();
    assert!(message.contains("velocity.png"), "{message}");
}

#[test]
fn extreme_values_do_not_break_the_axes() {
    let dir = out_dir("extreme");
    let mut wild = records(20, 1.0, neutral);
    wild[3].position = Vector3::new(f64::MAX, -f64::MAX, 1e308);
    wild[4].velocity = Vector3::new(f64::MIN_POSITIVE, -1e-300, 0.0);
    wild[5].adaptation.nis = 1e300;
    wild[6].adaptation.fade = f64::INFINITY;
    wild[7].adaptation.inflation = 1e-300;
    // Times whose span is lost in rounding.
    let mut late = records(3, 1.0, neutral);
    for (i, r) in late.iter_mut().enumerate() {
        r.time = 1e12 + i as f64 * 1e-6;
    }
    for (label, records) in [("wild", &wild), ("late", &late)] {
        let traces = [FilterTrace { label, records }];
        let files = error_figures(&dir, "x", PositionAxes::NorthEastDown, &traces).unwrap();
        for pair in files.chunks(2) {
            png_size(&pair[0]);
            assert!(svg_text(&pair[1]).contains(label));
        }
    }
}

// --- CSV -------------------------------------------------------------------

#[test]
fn epochs_csv_has_the_header_one_row_per_record_and_round_trips() {
    let dir = out_dir("csv");
    std::fs::create_dir_all(&dir).unwrap();
    let mut recs = records(7, 0.1 + 0.2, |t| Adaptation {
        nis: t / 3.0,
        rejected: t == 0.2,
        fade: 1.0 + t,
        inflation: 2.5,
        inflated: 2,
        compression: 0.125,
        alpha1: 1.0 / 3.0,
        noise_trace: 1e-300,
        ..Adaptation::default()
    });
    recs[3].velocity.y = f64::NAN;
    for (k, r) in recs.iter_mut().enumerate() {
        r.position_nees = Some(k as f64 * 0.75);
    }
    let path = dir.join("epochs.csv");
    write_epochs_csv(&path, PositionAxes::EastNorthUp, &recs).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert_eq!(
        text.lines().next().unwrap(),
        "time_s,pos_east_m,pos_north_m,pos_up_m,vel_north_mps,vel_east_mps,vel_down_mps,\
         att_north_deg,att_east_deg,att_down_deg,nis,rejected,fade,inflation,inflated,\
         compression,alpha1,noise_trace,nees"
    );
    assert_eq!(text.lines().count(), 1 + recs.len());
    let mut reader = csv::Reader::from_path(&path).unwrap();
    let rows: Vec<csv::StringRecord> = reader.records().map(Result::unwrap).collect();
    assert_eq!(rows.len(), recs.len());
    let same = |a: f64, b: f64| a == b || (a.is_nan() && b.is_nan());
    for (row, r) in rows.iter().zip(&recs) {
        let v: Vec<f64> = row.iter().map(|s| s.parse().unwrap()).collect();
        let deg = 180.0 / std::f64::consts::PI;
        let a = &r.adaptation;
        let expected = [
            r.time,
            r.position.y,
            r.position.x,
            -r.position.z,
            r.velocity.x,
            r.velocity.y,
            r.velocity.z,
            r.attitude.x * deg,
            r.attitude.y * deg,
            r.attitude.z * deg,
            a.nis,
            if a.rejected { 1.0 } else { 0.0 },
            a.fade,
            a.inflation,
            a.inflated as f64,
            a.compression,
            a.alpha1,
            a.noise_trace,
            r.position_nees.unwrap(),
        ];
        assert_eq!(v.len(), expected.len());
        for (k, (got, want)) in v.iter().zip(expected).enumerate() {
            assert!(same(*got, want), "column {k}: {got} vs {want}");
        }
    }
    // The third row, hand-formatted: t = 0.2 is the rejected update.
    assert_eq!(&rows[2][11], "1");
    assert_eq!(&rows[2][14], "2");
    assert_eq!(&rows[3][5], "NaN");
    assert_eq!(&rows[0][17], "1e-300");
}

#[test]
fn epochs_csv_in_north_east_down_and_without_records() {
    let dir = out_dir("csv-ned");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("empty.csv");
    write_epochs_csv(&path, PositionAxes::NorthEastDown, &[]).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert_eq!(text.lines().count(), 1);
    assert!(text.starts_with("time_s,pos_north_m,pos_east_m,pos_down_m,vel_north_mps,"));
}

/// Figures of real runs of built-in scenarios, to look at
/// (`cargo test -p kestrel-cli --test plots -- --ignored`; the files are
/// under the target directory's `tmp/plots/`). Seconds of trajectory per
/// scenario from `KESTREL_PLOT_SECONDS` (default 120).
#[test]
#[ignore = "slow; renders figures for inspection"]
fn figures_of_built_in_scenarios() {
    use kestrel_app::experiment::{run, RunOptions};
    let seconds: f64 = std::env::var("KESTREL_PLOT_SECONDS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(120.0);
    for name in ["000", "002", "003", "004"] {
        let scenario = kestrel_app::scenario::by_name(name).unwrap();
        let options = RunOptions::default().with_duration(seconds);
        let runs: Vec<(&str, Vec<EpochRecord>)> = scenario
            .filters
            .iter()
            .map(|kind| {
                let records = run(&scenario, kind, scenario.seed, &options)
                    .map(|r| r.records)
                    .unwrap_or_default();
                (kind.label(), records)
            })
            .collect();
        let traces: Vec<FilterTrace<'_>> = runs
            .iter()
            .map(|(label, records)| FilterTrace { label, records })
            .collect();
        let dir = out_dir(&format!("scenario-{name}"));
        let axes = PositionAxes::for_scenario(name);
        let title = format!("Scenario {name}");
        let files = error_figures(&dir, &title, axes, &traces).unwrap();
        write_epochs_csv(&dir.join("epochs.csv"), axes, &runs[0].1).unwrap();
        assert_eq!(files.len(), 8);
    }
}

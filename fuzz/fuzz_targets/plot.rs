//! The plot renderer on any data: NaN, infinities, all x or all y equal at any magnitude,
//! values a few ulps apart, huge and tiny ranges, log axes with non-positive values, any text.
//! SVG and PNG (one run in four) come back, in bounded time and memory, with no panic (nor a
//! drawing error: the renderer asserts none in debug builds); the SVG is one document; the PNG
//! has its signature, the size of the panels, its chunks in order, and is compressed.
#![no_main]

use arbitrary::{Result, Unstructured};
use libfuzzer_sys::fuzz_target;
use nf::plot::{H, Panel, Series, Style, W, render_png, render_svg};

/// A value: from the awkward ones, near a base (a few ulps), or anything.
fn value(u: &mut Unstructured, base: f64) -> Result<f64> {
    Ok(match u.int_in_range(0..=7u8)? {
        0 => u.arbitrary()?,
        1 => *u.choose(&[
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            0.0,
            -0.0,
            f64::MAX,
            f64::MIN,
            f64::MIN_POSITIVE,
            5e-324,
            1e-300,
            1e300,
        ])?,
        2 | 3 => base,
        4 | 5 => {
            let k: i8 = u.arbitrary()?;
            f64::from_bits(base.to_bits().wrapping_add_signed(k as i64))
        }
        _ => base * (1.0 + u.int_in_range(-1000i32..=1000)? as f64 * 1e-6),
    })
}

fn base(u: &mut Unstructured) -> Result<f64> {
    Ok(match u.int_in_range(0..=3u8)? {
        0 => u.arbitrary()?,
        1 => 10f64.powi(u.int_in_range(-320..=308)?) * if u.arbitrary()? { -1.0 } else { 1.0 },
        2 => u.int_in_range(-100_000i32..=100_000)? as f64,
        _ => 2000.0,
    })
}

fn text(u: &mut Unstructured) -> Result<String> {
    let s: String = u.arbitrary()?;
    Ok(s.chars().take(60).collect())
}

fn panel(u: &mut Unstructured) -> Result<Panel> {
    let mut series = Vec::new();
    for _ in 0..u.int_in_range(0..=7)? {
        let (bx, by) = (base(u)?, base(u)?);
        let mut points = Vec::new();
        for _ in 0..u.int_in_range(0..=48)? {
            points.push((value(u, bx)?, value(u, by)?));
        }
        series.push(Series {
            name: text(u)?,
            points,
            style: *u.choose(&[Style::Line, Style::Points, Style::Bars, Style::Spread])?,
        });
    }
    Ok(Panel {
        title: text(u)?,
        x_label: text(u)?,
        y_label: text(u)?,
        series,
        log_x: u.arbitrary()?,
        log_y: u.arbitrary()?,
    })
}

fn run(u: &mut Unstructured) -> Result<()> {
    let mut panels = Vec::new();
    for _ in 0..u.int_in_range(0..=3)? {
        panels.push(panel(u)?);
    }
    if std::env::var_os("NF_FUZZ_DEBUG").is_some() {
        eprintln!("{panels:#?}");
    }
    let svg = render_svg(&panels);
    assert!(svg.starts_with("<svg ") && svg.ends_with("</svg>\n"));
    assert_eq!(svg.matches("<svg").count(), 1);
    // Bounded by the data: a log axis over all of f64's 630 decades has a tick each.
    let series = panels.iter().map(|p| p.series.len()).sum::<usize>();
    let points: usize = panels.iter().flat_map(|p| &p.series).map(|s| s.points.len()).sum();
    let bound = 1_000 + 300 * points + 2_000 * series + 300_000 * panels.len();
    assert!(svg.len() < bound, "{} bytes", svg.len());

    // The PNG's drawing and compression are most of a run's time: one run in four draws it.
    if u.arbitrary::<u8>()? % 4 != 3 {
        return Ok(());
    }
    let png = render_png(&panels);
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    assert_eq!(&png[12..16], b"IHDR");
    assert_eq!(u32::from_be_bytes(png[16..20].try_into().unwrap()), W);
    let h = H * panels.len().max(1) as u32;
    assert_eq!(u32::from_be_bytes(png[20..24].try_into().unwrap()), h);
    // Chunks, each with its length, end to end: IHDR, at least one IDAT, IEND last.
    let (mut at, mut kinds) = (8, Vec::new());
    while at < png.len() {
        let len = u32::from_be_bytes(png[at..at + 4].try_into().unwrap()) as usize;
        kinds.push(&png[at + 4..at + 8]);
        at += 12 + len;
    }
    assert_eq!(at, png.len());
    assert_eq!((kinds[0], kinds[kinds.len() - 1]), (&b"IHDR"[..], &b"IEND"[..]));
    assert!(kinds.contains(&&b"IDAT"[..]));
    // Compressed: well under the image's 3 bytes a pixel.
    assert!(png.len() < (W * h) as usize, "{} bytes", png.len());
    Ok(())
}

fuzz_target!(|data: &[u8]| {
    let _ = run(&mut Unstructured::new(data));
});

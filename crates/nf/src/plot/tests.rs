use super::*;

fn panel() -> Panel {
    Panel {
        title: "a < b".into(),
        x_label: "x".into(),
        y_label: "y".into(),
        series: vec![
            Series {
                name: "line".into(),
                points: vec![(0.0, 1.0), (1.0, 2.0)],
                style: Style::Line,
            },
            Series {
                name: "pts".into(),
                points: vec![(0.5, 1.5), (f64::NAN, 0.0)],
                style: Style::Points,
            },
        ],
        log_x: false,
        log_y: false,
    }
}

/// Three panels as `nf fit` and `nf diagnose` draw them: a sine with its fit, scattered
/// residuals with error bars, and a log-log Allan deviation.
fn typical() -> Vec<Panel> {
    let gamma: Vec<f64> = (0..72).map(|k| k as f64 * 5.0).collect();
    let rate = |g: f64| 10.0 * (g - 300.0).to_radians().cos();
    let noise = |k: usize| ((k * 7919) % 101) as f64 / 101.0 - 0.5;
    let series = |name: &str, points: Vec<(f64, f64)>, style| Series {
        name: name.into(),
        points,
        style,
    };
    let fit = Panel {
        title: "gyro output, psi = 65.5347 deg".into(),
        x_label: "encoder angle gamma (deg)".into(),
        y_label: "rate (deg/h)".into(),
        series: vec![
            series("measured", gamma.iter().map(|&g| (g, rate(g))).collect(), Style::Points),
            series(
                "fitted A cos + B sin + C",
                gamma.iter().map(|&g| (g, rate(g))).collect(),
                Style::Line,
            ),
        ],
        log_x: false,
        log_y: false,
    };
    let res: Vec<(f64, f64)> = gamma.iter().enumerate().map(|(k, &g)| (g, 0.01 * noise(k))).collect();
    let bars = res
        .iter()
        .flat_map(|&(g, r)| [(g, r - 0.003), (g, r + 0.003)])
        .collect();
    let residuals = Panel {
        title: "residuals, RSS = 1.214e-3 (deg/h)^2".into(),
        x_label: "encoder angle gamma (deg)".into(),
        y_label: "residual (deg/h)".into(),
        series: vec![
            series("residual", res, Style::Points),
            series("1 sigma", bars, Style::Bars),
        ],
        log_x: false,
        log_y: false,
    };
    let taus: Vec<f64> = (0..14).map(|k| 2f64.powi(k)).collect();
    let allan = Panel {
        title: "Allan deviation of the residuals in time order".into(),
        x_label: "tau (s)".into(),
        y_label: "sigma (deg/h)".into(),
        series: vec![series(
            "adev",
            taus.iter().map(|&t| (t, 0.05 / t.sqrt())).collect(),
            Style::Line,
        )],
        log_x: true,
        log_y: true,
    };
    vec![fit, residuals, allan]
}

#[test]
fn svg_has_every_series_the_title_and_the_labels_as_text() {
    let s = render_svg(&[panel(), panel()]);
    assert!(s.starts_with("<svg") && s.ends_with("</svg>\n"), "{s}");
    // A line and its legend's marker in each panel.
    assert_eq!(s.matches(r##"stroke="#1F77B4""##).count(), 4);
    // One dot (the NaN is left out) and the legend's marker in each panel.
    assert_eq!(s.matches("<circle").count(), 4);
    assert_eq!(s.matches(r##"fill="#D62728""##).count(), 4);
    assert_eq!(s.matches("\na &lt; b\n</text>").count(), 2);
    assert!(s.contains("\npts\n</text>") && s.contains("\n1.5\n</text>"));
    assert!(!s.contains("NaN") && !s.contains("inf"));
    assert!(write("/tmp/x.gif", &[]).is_err());
}

#[test]
fn log_axes_leave_out_what_they_cannot_show() {
    let mut p = panel();
    (p.log_x, p.log_y) = (true, true);
    p.series.push(Series {
        name: "ci".into(),
        points: vec![(1.0, 1.0), (1.0, 2.0), (0.5, -1.0), (0.5, 3.0)],
        style: Style::Bars,
    });
    // y = -1 cannot be drawn on a log axis: one bar of the two, and the legend's marker.
    let svg = render_svg(&[p]);
    assert_eq!(svg.matches(r##"stroke="#2CA02C""##).count(), 2, "{svg}");
    // Less than a decade on each: round linear ticks where 1, 2, 3 and 5 give too few.
    assert!(
        svg.contains("\n0.6\n</text>") && svg.contains("\n3\n</text>") && !svg.contains("\n2.5\n</text>"),
        "{svg}"
    );
    assert!(!svg.contains("NaN") && !svg.contains("inf"));
}

#[test]
fn a_typical_png_is_compressed_and_decodes_to_the_panels_size() {
    let png = render_png(&typical());
    assert!(png.len() < 200_000, "{} bytes", png.len());
    let img = image::load_from_memory_with_format(&png, image::ImageFormat::Png).unwrap();
    assert_eq!((img.width(), img.height()), (W, 3 * H));
    // Not blank: the text and the series are there in colour.
    let rgb = img.to_rgb8();
    let blue = rgb.pixels().filter(|p| p.0 == [31, 119, 180]).count();
    let dark = rgb.pixels().filter(|p| p.0.iter().all(|&c| c < 80)).count();
    assert!(blue > 500 && dark > 2_000, "{blue} {dark}");
    let svg = render_svg(&typical());
    for t in [
        "\ngyro output, psi = 65.5347 deg\n",
        "\nresidual (deg/h)\n",
        "\n1 sigma\n",
    ] {
        assert!(svg.contains(t), "{t}");
    }
}

#[test]
fn long_titles_get_smaller_then_wrap_and_control_characters_go() {
    let mut p = panel();
    p.title = format!(
        "Allan deviation of {}/run\u{7}.csv",
        "/a-long-directory-name".repeat(12)
    );
    p.series[1].name = "a legend entry far too long to fit ".repeat(4);
    let svg = render_svg(&[p]);
    assert!(
        svg.contains("Allan deviation of\n</text>") && !svg.contains('\u{7}'),
        "{svg}"
    );
    // The legend's text is smaller than the ticks' (14 / 1.24 in SVG).
    let name = svg.find("a legend entry far").unwrap();
    let size = svg[..name].rsplit("font-size=\"").next().unwrap();
    let size: f64 = size[..size.find('"').unwrap()].parse().unwrap();
    assert!(size < 11.0, "{size}");
    // By width: 3 units a character.
    let w = |s: &str| 3 * s.chars().count() as u32;
    assert_eq!(draw::wrap("ab cd ef", 15, 3, w), vec!["ab cd", "ef"]);
    assert_eq!(draw::wrap("abcdefgh", 9, 3, w), vec!["abc", "def", "gh"]);
    assert_eq!(draw::wrap("abcdefghijklm", 9, 2, w), vec!["abc", "..."]);
    assert_eq!(draw::wrap("", 9, 2, w), vec![""]);
}

#[test]
fn degenerate_data_draws_in_finite_time() {
    // All x equal at about 2000 or more (or a few ulps apart): the tick step fell below the
    // spacing of floats there, `t += step` stood still and the tick list grew until the
    // memory ran out. Found by the `plot` fuzz target.
    let odd = [
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::MAX,
        -f64::MAX,
        5e-324,
        0.0,
    ];
    for v in [2000.0f64, 2048.0, -52077.00000000004, 1e6, 1e20, -1e300, 1e300] {
        for w in [v, f64::from_bits(v.to_bits() + 1), f64::from_bits(v.to_bits() + 3)] {
            let mut p = panel();
            p.series[0].points = vec![(v, 1.0), (w, 2.0)];
            p.series[1].points = vec![(v, 0.5), (w, 1.5)];
            let mut q = panel();
            q.series[0].points = vec![(0.0, v), (1.0, w)];
            q.series[1].points = odd.iter().map(|&o| (o, v)).collect();
            (q.log_x, q.log_y) = (v > 1e10, v > 1e10);
            let mut e = panel();
            e.series.iter_mut().for_each(|s| s.points.clear());
            e.series.push(Series {
                name: String::new(),
                points: vec![],
                style: Style::Bars,
            });
            let panels = [p, q, e];
            assert!(render_svg(&panels).ends_with("</svg>\n"));
            assert_eq!(render_png(&panels)[..8], *b"\x89PNG\r\n\x1a\n");
        }
    }
    assert!(render_svg(&[]).ends_with("</svg>\n"));
    assert_eq!(render_png(&[])[..4], *b"\x89PNG");
}

#[test]
fn write_chooses_the_format_by_the_ending() {
    let dir = std::env::temp_dir().join(format!("nf-plot-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (svg, png) = (dir.join("p.SVG"), dir.join("p.png"));
    write(svg.to_str().unwrap(), &[panel()]).unwrap();
    write(png.to_str().unwrap(), &[panel()]).unwrap();
    assert!(std::fs::read_to_string(&svg).unwrap().starts_with("<svg"));
    assert_eq!(std::fs::read(&png).unwrap()[..4], *b"\x89PNG");
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn stacked_panels_share_their_plotting_areas_left_edge() {
    // Short tick labels above, long ones below: the plots start at the same x.
    let mut long = panel();
    long.series[0].points = vec![(0.0, 0.00123), (1.0, 0.00456)];
    long.series[1].points = vec![(0.5, 0.0031)];
    let svg = render_svg(&[panel(), long]);
    // A horizontal grid line starts at its plot's left edge.
    let lefts: std::collections::BTreeSet<&str> = svg
        .lines()
        .filter(|l| l.starts_with("<line") && l.contains(r##"stroke="#DDDDDD""##))
        .filter_map(|l| {
            let attr = |k: &str| l.split(&format!(" {k}=\"")).nth(1)?.split('"').next();
            (attr("y1")? == attr("y2")?).then(|| attr("x1")).flatten()
        })
        .collect();
    assert_eq!(lefts.len(), 1, "{lefts:?}");
}

#[test]
fn a_spread_takes_the_colour_of_the_series_before_it_and_no_legend_entry() {
    let mut p = panel();
    p.series.insert(
        1,
        Series {
            name: "not shown".into(),
            points: vec![(0.0, 0.5), (0.0, 1.5), (1.0, 1.5), (1.0, 2.5)],
            style: Style::Spread,
        },
    );
    let svg = render_svg(&[p]);
    // The line, its legend marker and the two bars in the line's colour; the points after
    // keep the second colour.
    assert_eq!(svg.matches(r##"stroke="#1F77B4""##).count(), 4, "{svg}");
    assert_eq!(svg.matches(r##"fill="#D62728""##).count(), 2, "{svg}");
    assert!(!svg.contains("not shown"));
}

#[test]
fn dots_and_lines_drawn_before_others_are_larger_so_that_coinciding_ones_show() {
    let mut p = panel();
    p.series.push(Series {
        name: "after".into(),
        points: vec![(0.5, 1.5)],
        style: Style::Points,
    });
    p.series.push(Series {
        name: "model".into(),
        points: vec![(0.0, 1.0), (1.0, 2.0)],
        style: Style::Line,
    });
    let svg = render_svg(&[p]);
    // The first dots ring the second's at the same place, the first line the second; the
    // legend's markers stay as they were.
    assert_eq!(svg.matches(r#"r="4""#).count(), 1, "{svg}");
    assert_eq!(svg.matches(r#"r="3""#).count(), 3, "{svg}");
    assert_eq!(svg.matches(r#"stroke-width="3""#).count(), 1, "{svg}");
    assert_eq!(svg.matches(r#"stroke-width="2""#).count(), 3, "{svg}");
}

#[test]
fn a_legend_with_no_room_inside_goes_beside_the_plot() {
    // Seven lines across the whole plot, as an Allan plot's terms: every corner is reached,
    // and room above them for seven entries would squeeze the data to a third.
    let lines = (0..7)
        .map(|k| Series {
            name: format!("term {k}"),
            points: vec![(0.0, k as f64), (1.0, 6.0 - k as f64)],
            style: Style::Line,
        })
        .collect();
    let p = Panel {
        title: "t".into(),
        x_label: "x".into(),
        y_label: "y".into(),
        series: lines,
        log_x: false,
        log_y: false,
    };
    let svg = render_svg(&[p]);
    let rect = |stroke: &str| -> (f64, f64) {
        let at = svg.find(&format!("fill=\"none\" stroke=\"{stroke}\"")).unwrap();
        let tag = &svg[svg[..at].rfind("<rect").unwrap()..at];
        let num = |key: &str| -> f64 {
            let v = &tag[tag.find(key).unwrap() + key.len()..];
            v[..v.find('"').unwrap()].parse().unwrap()
        };
        (num(" x=\""), num(" width=\""))
    };
    let (frame_x, frame_w) = rect("#444444");
    let (legend_x, legend_w) = rect("#DDDDDD");
    assert!(
        legend_x >= frame_x + frame_w,
        "the legend at {legend_x} inside the plot to {}",
        frame_x + frame_w
    );
    assert!(legend_x + legend_w <= f64::from(W), "{legend_x} + {legend_w}");
    for k in 0..7 {
        assert!(svg.contains(&format!("term {k}")), "entry {k}");
    }
}

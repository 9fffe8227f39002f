//! The reader on recordings as other programs write them, and on every kind of bad line.

use nf::recording::{Recording, Row, index_gaps};

const GOOD: &str = "\
# format = northfinder-recording/1
# latitude_deg = 43.8
# instrument = bench unit 2
index,t_s,encoder_deg,rate_dph,tilt_x_deg,tilt_y_deg
0,1.0,0.0,4.5,0.001,0.002
1,3.2,90.0,-9.9,0.000,0.001
2,5.4,180.0,-4.5,-0.001,0.000
3,7.6,270.0,9.9,0.000,-0.001
";

#[test]
fn reads_the_documented_layout() {
    let r = Recording::parse(GOOD).unwrap();
    assert_eq!(r.latitude_deg, 43.8);
    assert_eq!(r.rows.len(), 4);
    assert_eq!(r.rows[1].encoder_deg, 90.0);
    assert_eq!(r.rows[3].line, 8);
    assert!(r.has_tilt_xy());
    assert_eq!(r.meta["instrument"], "bench unit 2");
    assert_eq!(r.rows[0].samples, None);
}

#[test]
fn any_column_order_extra_columns_quotes_and_crlf() {
    let text = "# latitude_deg = 43.8\r\n# format = northfinder-recording/1\r\n# operator = someone\r\n\
\"rate_dph\",comment,encoder_deg,t_s,index,samples\r\n\
4.5,hello,0.0,1.0,0,2000\r\n\"-9.9\",x,90.0,3.2,1,2000\r\n\r\n";
    let r = Recording::parse(text).unwrap();
    assert_eq!(r.rows.len(), 2);
    assert_eq!(
        (r.rows[1].rate_dph, r.rows[1].encoder_deg, r.rows[1].samples),
        (-9.9, 90.0, Some(2000))
    );
    assert!(!r.has_tilt_x());
}

#[test]
fn empty_or_nan_optional_cells_are_missing_values() {
    let text = "# format = northfinder-recording/1\n# latitude_deg = 10\nindex,t_s,encoder_deg,rate_dph,temp_c,q1_dph,q2_dph,q3_dph,q4_dph\n0,1,0,2.5,,1,2,3,4\n1,2,90,1,NaN,1,2,,4\n";
    let r = Recording::parse(text).unwrap();
    assert_eq!(r.rows[0].temp_c, None);
    assert_eq!(r.rows[0].quarters_dph, Some([1.0, 2.0, 3.0, 4.0]));
    assert_eq!(r.rows[1].quarters_dph, None);
    // Each column with a blank is said once, at its first line, with its lines.
    let said: Vec<(usize, String)> = r.warnings.iter().map(|w| (w.line, w.what.clone())).collect();
    assert_eq!(
        said,
        [
            (
                5,
                "q1_dph .. q4_dph: no value on 1 of 2 positions (line 5): read as not recorded there".to_string()
            ),
            (
                4,
                "temp_c: no value on 2 of 2 positions (lines 4, 5): read as not recorded there".to_string()
            ),
        ]
    );
    let full = Recording::parse(GOOD).unwrap();
    assert!(full.warnings.is_empty(), "{:?}", full.warnings);
    // A dwell mean of no samples is kept, and said.
    let none = Recording::parse(
        "# format = northfinder-recording/1\n# latitude_deg = 10\nindex,t_s,encoder_deg,rate_dph,samples\n0,1,0,2.5,100\n1,2,90,1,0\n",
    )
    .unwrap();
    let said: Vec<(usize, &str)> = none.warnings.iter().map(|w| (w.line, w.what.as_str())).collect();
    assert_eq!(
        said,
        [(5, "samples is 0: rate_dph is the mean of no samples; used as given")]
    );
}

fn error(text: &str) -> (usize, String) {
    let e = Recording::parse(text).unwrap_err();
    (e.line, e.to_string())
}

const HEAD: &str = "# format = northfinder-recording/1\n# latitude_deg = 43.8\nindex,t_s,encoder_deg,rate_dph\n";

#[test]
fn every_bad_recording_names_the_line_and_the_problem() {
    let cases: &[(&str, usize, &str)] = &[
        ("", 0, "no header"),
        (
            "# latitude_deg = 43.8\nindex,t_s,encoder_deg,rate_dph\n0,1,0,1\n",
            0,
            "'format' is missing",
        ),
        (
            "# format = northfinder-recording/2\n# latitude_deg = 1\nindex,t_s,encoder_deg,rate_dph\n0,1,0,1\n",
            1,
            "not supported",
        ),
        (
            "# format = northfinder-recording/1\nindex,t_s,encoder_deg,rate_dph\n0,1,0,1\n",
            0,
            "latitude_deg' is missing",
        ),
        (
            "# format = northfinder-recording/1\n# latitude_deg = 91\nindex,t_s,encoder_deg,rate_dph\n0,1,0,1\n",
            2,
            "not a latitude",
        ),
        (
            "# format = northfinder-recording/1\n# latitude_deg = north\nindex,t_s,encoder_deg,rate_dph\n",
            2,
            "not a latitude",
        ),
        (
            "# format = northfinder-recording/1\n# latitude_deg = nan\nindex,t_s,encoder_deg,rate_dph\n0,1,0,1\n",
            2,
            "not a latitude",
        ),
        (
            "# format = northfinder-recording/1\n# latitude_deg = 90\nindex,t_s,encoder_deg,rate_dph\n0,1,0,1\n",
            2,
            "is a pole",
        ),
        (
            "# latitude_deg = -90\n# format = northfinder-recording/1\nindex,t_s,encoder_deg,rate_dph\n0,1,0,1\n",
            1,
            "no north to find",
        ),
        (
            "# format = northfinder-recording/1\n# latitude_deg\nindex,t_s,encoder_deg,rate_dph\n",
            2,
            "without '='",
        ),
        (
            "# format = northfinder-recording/1\n# format = northfinder-recording/2\nindex\n",
            2,
            "given twice with different values (first on line 1)",
        ),
        (
            "# format = northfinder-recording/1\n# latitude_deg = 4\nindex,t_s,rate_dph\n0,1,2\n",
            3,
            "'encoder_deg' is missing",
        ),
        (
            "# format = northfinder-recording/1\n# latitude_deg = 4\nindex,t_s,encoder_deg,rate_dph,t_s\n",
            3,
            "appears twice",
        ),
        (HEAD, 0, "no positions"),
        (
            "# format = northfinder-recording/1\n# Latitude_deg = 4\nindex,t_s,encoder_deg,rate_dph\n0,1,0,1\n",
            0,
            "'latitude_deg' is missing; line 2 has 'Latitude_deg' (keys are case-sensitive)",
        ),
    ];
    for (text, line, what) in cases {
        let (l, msg) = error(text);
        assert_eq!(l, *line, "{msg}");
        assert!(msg.contains(what), "'{msg}' should say '{what}'");
    }
    let rows: &[(&str, &str)] = &[
        ("0,1,0", "3 fields, the header has 4"),
        ("0,1,0,1,5", "5 fields"),
        ("0,1,0,fast", "rate_dph 'fast' is not a finite number"),
        ("0,1,0,", "rate_dph is empty"),
        ("0,1,0,inf", "not a finite number"),
        ("0,1,360,1", "encoder_deg 360 is outside"),
        ("0,1,-0.5,1", "outside"),
        ("-1,1,0,1", "index '-1' is not a whole number"),
        ("1.5,1,0,1", "is not a whole number"),
        ("0,nan,0,1", "t_s 'nan' is not a finite number"),
        ("0,1,0,1e300", "rate_dph 1e300 is beyond any gyro's range"),
        ("0,1,0,-1e12", "beyond any gyro's range"),
    ];
    for (row, what) in rows {
        let text = format!("{HEAD}9,0.5,10,1\n{row}\n");
        let (l, msg) = error(&text);
        assert_eq!(l, 5, "{msg}");
        assert!(
            msg.starts_with("line 5: ") && msg.contains(what),
            "'{msg}' should say '{what}'"
        );
    }
    let opt = "# format = northfinder-recording/1\n# latitude_deg = 1\nindex,t_s,encoder_deg,rate_dph,samples,rate_sd_dph,tilt_x_deg\n";
    for (row, what) in [
        ("0,1,0,1,12.5,0.1,0", "samples 12.5"),
        // Beyond a count's range it was read as 4294967295 without a word.
        ("0,1,0,1,1e23,0.1,0", "samples 100000000000000000000000 is not a count"),
        ("0,1,0,1,5,-0.1,0", "negative"),
        ("0,1,0,1,5,0.1,level", "tilt_x_deg 'level'"),
    ] {
        let (l, msg) = error(&format!("{opt}{row}\n"));
        assert_eq!(l, 4, "{msg}");
        assert!(msg.contains(what), "'{msg}' should say '{what}'");
    }
}

#[test]
fn a_tilt_beyond_90_deg_is_no_reading_and_a_warning() {
    let head = "# format = northfinder-recording/1\n# latitude_deg = 1\nindex,t_s,encoder_deg,rate_dph,tilt_x_deg,tilt_y_deg\n";
    let r = Recording::parse(&format!("{head}0,1,0,1,0.01,-9999\n1,2,90,1,95,0.02\n")).unwrap();
    let tilts: Vec<_> = r.rows.iter().map(|r| (r.tilt_x_deg, r.tilt_y_deg)).collect();
    assert_eq!(tilts, [(Some(0.01), None), (None, Some(0.02))]);
    let said: Vec<String> = r.warnings.iter().map(|w| w.to_string()).collect();
    assert_eq!(said.len(), 2);
    assert!(
        said[0].starts_with("line 4: tilt_y_deg -9999 is not an elevation"),
        "{said:?}"
    );
    assert!(
        said[1].starts_with("line 5: tilt_x_deg 95 is not an elevation"),
        "{said:?}"
    );
}

#[test]
fn a_last_position_without_its_line_end_is_read_with_a_warning() {
    // A file cut short while written: its last value may be cut too ("6.913" read as "6.").
    let cut = GOOD.trim_end();
    let r = Recording::parse(cut).unwrap();
    assert_eq!(r.rows.len(), 4);
    let said: Vec<String> = r.warnings.iter().map(|w| w.to_string()).collect();
    assert_eq!(said.len(), 1, "{said:?}");
    assert!(
        said[0].starts_with("line 8: the last position has no line end")
            && said[0].contains("its last value ('-0.001') perhaps cut too"),
        "{said:?}"
    );
    assert!(Recording::parse(GOOD).unwrap().warnings.is_empty());
    assert!(Recording::parse(&format!("{GOOD}# end")).unwrap().warnings.len() == 1);
}

#[test]
fn a_malformed_dwell_or_sample_rate_is_an_error_at_its_line() {
    for (key, v) in [
        ("dwell_s", "abc"),
        ("dwell_s", "-2"),
        ("dwell_s", "0"),
        ("dwell_s", "inf"),
        ("sample_rate_hz", "fast"),
    ] {
        let (line, msg) = error(&format!(
            "# format = northfinder-recording/1\n# latitude_deg = 1\n# {key} = {v}\nindex,t_s,encoder_deg,rate_dph\n0,1,0,1\n"
        ));
        assert_eq!(line, 3, "{msg}");
        assert!(msg.contains(&format!("{key} '{v}' is not a positive number")), "{msg}");
    }
}

#[test]
fn dwells_longer_than_their_spacing_are_a_warning() {
    let text = "# format = northfinder-recording/1\n# latitude_deg = 1\n# dwell_s = 2.5\nindex,t_s,encoder_deg,rate_dph\n0,1,0,1\n1,4,90,1\n2,6,180,1\n";
    let r = Recording::parse(text).unwrap();
    let said: Vec<String> = r.warnings.iter().map(|w| w.to_string()).collect();
    assert_eq!(said.len(), 1, "{said:?}");
    assert!(
        said[0].starts_with("line 3: dwell_s 2.5 s is longer than the 2 s between the centres of lines 6 and 7"),
        "{said:?}"
    );
    assert!(Recording::parse(&text.replace("2.5", "2")).unwrap().warnings.is_empty());
}

#[test]
fn quarters_that_do_not_average_to_their_rate_are_dropped_with_a_warning() {
    let head = "# format = northfinder-recording/1\n# latitude_deg = 1\nindex,t_s,encoder_deg,rate_dph,q1_dph,q2_dph,q3_dph,q4_dph\n";
    // Row 1: one quarter corrupted by 5 deg/h while the rate stayed. Row 2: quarters of unequal
    // sample counts (3, 4, 3, 4 of 14), whose plain mean is a little off the rate.
    let q = [1.01, 0.99, 1.02, 0.98];
    let weighted = (3.0 * q[0] + 4.0 * q[1] + 3.0 * q[2] + 4.0 * q[3]) / 14.0;
    let text = format!(
        "{head}0,1,0,1,1.01,0.99,1.02,0.98\n1,2,90,1,1.01,0.99,6.02,0.98\n2,3,180,{weighted},1.01,0.99,1.02,0.98\n"
    );
    let r = Recording::parse(&text).unwrap();
    let kept: Vec<bool> = r.rows.iter().map(|r| r.quarters_dph.is_some()).collect();
    assert_eq!(kept, [true, false, true]);
    let said: Vec<String> = r.warnings.iter().map(|w| w.to_string()).collect();
    assert_eq!(said.len(), 1, "{said:?}");
    assert!(said[0].starts_with("line 5: q1_dph..q4_dph average"), "{said:?}");
}

#[test]
fn quarters_written_with_fewer_digits_than_their_rate_are_kept() {
    // Quarters to two decimals: their mean is off the rate by up to half a hundredth, which
    // a fifth of their spread need not cover (an outside audit's writer: dropped in 40 of 40).
    let head = "# format = northfinder-recording/1\n# latitude_deg = 1\nindex,t_s,encoder_deg,rate_dph,q1_dph,q2_dph,q3_dph,q4_dph\n";
    let text = format!(
        "{head}0,1,0,-12.2894,-12.29,-12.29,-12.29,-12.28\n1,2,90,-3.1102,-3.11,-3.12,-3.11,-3.10\n2,3,180,-12.2894,-12.29,-12.29,7.71,-12.28\n"
    );
    let r = Recording::parse(&text).unwrap();
    let kept: Vec<bool> = r.rows.iter().map(|r| r.quarters_dph.is_some()).collect();
    assert_eq!(kept, [true, true, false], "{:?}", r.warnings);
    // The same quarters to six decimals are held to six.
    let exact = text.replace(
        "-12.29,-12.29,-12.29,-12.28",
        "-12.290000,-12.290000,-12.290000,-12.280000",
    );
    let r = Recording::parse(&exact).unwrap();
    assert!(r.rows[0].quarters_dph.is_none(), "{:?}", r.rows[0]);
}

#[test]
fn gaps_name_the_missing_indices_and_the_lines_around() {
    let row = |index, line| Row {
        line,
        index,
        t_s: 0.0,
        encoder_deg: 0.0,
        rate_dph: 0.0,
        rate_sd_dph: None,
        samples: None,
        temp_c: None,
        tilt_x_deg: None,
        tilt_y_deg: None,
        quarters_dph: None,
    };
    let rows = [row(1, 10), row(2, 12), row(5, 20), row(6, 22)];
    let g = index_gaps(&rows);
    assert_eq!(g.len(), 2);
    assert_eq!(
        (g[0].first, g[0].last, g[0].after_line, g[0].before_line),
        (0, 0, None, 10)
    );
    assert_eq!(
        (g[1].first, g[1].last, g[1].after_line, g[1].before_line),
        (3, 4, Some(12), 20)
    );
    assert!(index_gaps(&rows[..2][1..]).len() == 1 && index_gaps(&[row(0, 3), row(1, 4)]).is_empty());
}

#[test]
fn visits_the_indices_skip_are_a_warning_and_the_rest_is_read() {
    // Indices from 1, and 4-5 gone: visits 0, 4 and 5 were lost from the file.
    let r = Recording::parse(&format!("{HEAD}1,2,90,0\n2,3,180,-1\n3,4,270,0\n6,5,45,0.7\n")).unwrap();
    assert_eq!(r.rows.len(), 4);
    let said: Vec<String> = r.warnings.iter().map(|w| w.to_string()).collect();
    assert_eq!(
        said,
        [
            "line 4: index 0 missing before this line's index 1: visits lost from the file",
            "line 7: indices 4 to 5 missing before this line's index 6: visits lost from the file"
        ]
    );
    let whole = Recording::parse(&format!("{HEAD}0,1,0,1\n1,2,90,0\n2,3,180,-1\n")).unwrap();
    assert!(whole.warnings.is_empty(), "{:?}", whole.warnings);
}

#[test]
fn lines_out_of_visiting_order_are_taken_by_index_and_time_must_follow_it() {
    let shuffled = Recording::parse(&format!("{HEAD}1,2,90,0\n0,1,0,1\n2,3,180,-1\n")).unwrap();
    let order: Vec<(u32, usize)> = shuffled.rows.iter().map(|r| (r.index, r.line)).collect();
    assert_eq!(order, [(0, 5), (1, 4), (2, 6)]);
    assert!(
        shuffled.warnings[0].what.contains("index order"),
        "{:?}",
        shuffled.warnings
    );
    assert!(Recording::parse(GOOD).unwrap().warnings.is_empty());
    for (rows, line, what) in [
        (
            "0,2,0,1\n1,1,90,0\n",
            5,
            "t_s 1 of index 1 is not after t_s 2 of index 0 (line 4)",
        ),
        ("0,1,0,1\n1,1,90,0\n", 5, "is not after"),
        (
            "1,1,90,0\n0,2,0,1\n",
            4,
            "t_s 1 of index 1 is not after t_s 2 of index 0 (line 5)",
        ),
    ] {
        let (l, msg) = error(&format!("{HEAD}{rows}"));
        assert_eq!(l, line, "{msg}");
        assert!(msg.contains(what), "'{msg}' should say '{what}'");
    }
}

#[test]
fn repeated_metadata_and_columns_the_reader_does_not_use_are_ignored() {
    let text = "# format = northfinder-recording/1\n# operator = A\n# latitude_deg = 10\n# operator = B\n\
                index,note,t_s,encoder_deg,rate_dph,note\n0,a,1,0,1,b\n1,c,2,90,0,d\n";
    let r = Recording::parse(text).unwrap();
    assert_eq!((r.rows.len(), r.meta["operator"].as_str()), (2, "A"));
    let (l, msg) = error(&text.replace("# operator = B", "# latitude_deg = 11"));
    assert_eq!(
        (l, msg.as_str()),
        (
            4,
            "line 4: metadata key 'latitude_deg' given twice with different values (first on line 3)"
        )
    );
}

#[test]
fn a_byte_that_is_not_utf8_in_a_column_no_one_reads_is_harmless() {
    let dir = std::env::temp_dir().join(format!("nf-latin1-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("run.csv");
    let mut bytes = HEAD.replace("rate_dph\n", "rate_dph,operator\n").into_bytes();
    bytes.extend_from_slice(b"0,1,0,1,Jos\xe9\n1,2,90,0,Jos\xe9\n");
    std::fs::write(&path, &bytes).unwrap();
    let r = Recording::read(path.to_str().unwrap()).unwrap();
    assert_eq!(r.rows.len(), 2);
    bytes.extend_from_slice(b"2,3,18\xb00,0,x\n");
    std::fs::write(&path, &bytes).unwrap();
    let e = Recording::read(path.to_str().unwrap()).unwrap_err();
    assert_eq!(e.line, 6, "{e}");
    assert!(e.to_string().contains("encoder_deg"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_missing_file_says_so() {
    let e = Recording::read("/nonexistent/run.csv").unwrap_err();
    assert_eq!(e.line, 0);
    assert!(
        e.at("/nonexistent/run.csv")
            .starts_with("/nonexistent/run.csv: cannot read it: "),
        "{e}"
    );
}

#[test]
fn utf16_is_refused_by_name() {
    let dir = std::env::temp_dir().join(format!("nf-utf16-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("run.csv");
    let mut bytes = vec![0xFF, 0xFE];
    bytes.extend(GOOD.encode_utf16().flat_map(u16::to_le_bytes));
    std::fs::write(&path, &bytes).unwrap();
    let e = Recording::read(path.to_str().unwrap()).unwrap_err();
    assert_eq!(e.line, 1);
    assert!(e.to_string().contains("UTF-16"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn free_text_before_the_header_is_a_comment_unless_it_names_a_key() {
    let text = format!("# recorded by rig 4\n{GOOD}");
    let r = Recording::parse(&text).unwrap();
    assert_eq!(r.rows.len(), 4);
    assert_eq!(r.warnings.len(), 1);
    assert!(
        r.warnings[0]
            .to_string()
            .starts_with("line 1: free text before the header")
    );
    let (l, msg) = error(&GOOD.replace("unit 2\n", "unit 2\n# dwell_s 2\n"));
    assert_eq!(
        (l, msg.as_str()),
        (
            4,
            "line 4: metadata line without '=': '# dwell_s 2' (expected '# key = value')"
        )
    );
}

#[test]
fn a_byte_order_mark_is_accepted() {
    let r = Recording::parse(&format!("\u{FEFF}{GOOD}")).unwrap();
    assert_eq!((r.rows.len(), r.rows[0].line), (4, 5));
}

#[test]
fn a_repeated_index_is_an_error_unless_the_line_is_an_exact_copy() {
    // The copy (spaces and quotes aside) is dropped with a warning naming both lines.
    let text = format!("{HEAD}0,1,0,4.5\n1,3,90,-9.9\n1, 3,\"90\",-9.9\n2,5,180,-4.5\n");
    let r = Recording::parse(&text).unwrap();
    assert_eq!(r.rows.iter().map(|r| r.index).collect::<Vec<_>>(), [0, 1, 2]);
    assert_eq!(r.warnings.len(), 1);
    assert_eq!(r.warnings[0].line, 6);
    assert!(
        r.warnings[0].to_string().contains("repeats line 5 exactly"),
        "{:?}",
        r.warnings
    );
    // The same index with other values: which is the measurement? Both lines are named.
    let (l, msg) = error(&format!("{HEAD}0,1,0,4.5\n1,3,90,-9.9\n2,5,180,-4.5\n1,7,90,-9.8\n"));
    assert_eq!(l, 7);
    assert!(msg.contains("index 1 appears on lines 5 and 7"), "{msg}");
    // The same angle at another time and index is a second visit, not a duplicate.
    let r = Recording::parse(&format!("{HEAD}0,1,0,4.5\n1,3,90,-9.9\n2,5,90,-9.8\n3,7,0,4.4\n")).unwrap();
    assert!(r.warnings.is_empty() && r.rows.len() == 4);
}

#[test]
fn a_shaft_that_did_not_turn_is_said_plainly() {
    let stuck: String = (0..36).map(|i| format!("{i},{},10,1\n", i + 1)).collect();
    let e = Recording::parse(&format!("{HEAD}{stuck}"))
        .unwrap()
        .require_turning()
        .unwrap_err();
    assert!(e.contains("1 distinct angle(s) over 36 positions (10 deg)"), "{e}");
    let two: String = (0..36).map(|i| format!("{i},{},{},1\n", i + 1, 90 * (i % 2))).collect();
    assert!(
        Recording::parse(&format!("{HEAD}{two}"))
            .unwrap()
            .require_turning()
            .is_err()
    );
    let three = format!("{HEAD}0,1,0,1\n1,2,120,1\n2,3,240.0000001,1\n");
    assert!(Recording::parse(&three).unwrap().require_turning().is_ok());
}

#[test]
fn a_hash_line_among_the_positions_is_named_and_late_metadata_refused() {
    let text = "# format = northfinder-recording/1\n# latitude_deg = 45\nindex,t_s,encoder_deg,rate_dph\n\
                0,1,0,1\n#1,2,90,0\n2,3,180,-1\n3,4,270,0\n";
    let r = Recording::parse(text).unwrap();
    assert_eq!(r.rows.len(), 3);
    assert!(
        r.warnings
            .iter()
            .any(|w| w.line == 5 && w.what.contains("'#' lines among the positions (line 5)")),
        "{:?}",
        r.warnings
    );
    let late = text.replace("#1,2,90,0", "# latitude_deg = 10");
    let (l, msg) = error(&late);
    assert_eq!(
        (l, msg.as_str()),
        (
            5,
            "line 5: metadata 'latitude_deg' after the header, where '#' lines are comments: metadata goes before the header"
        )
    );
    let again = text.replace("# latitude_deg = 45\n", "# latitude_deg = 45\n# latitude_deg = 45\n");
    assert_eq!(Recording::parse(&again).unwrap().latitude_deg, 45.0);
}

#[test]
fn quarters_equal_in_every_dwell_are_not_quarters() {
    let mut text = String::from(
        "# format = northfinder-recording/1\n# latitude_deg = 45\nindex,t_s,encoder_deg,rate_dph,q1_dph,q2_dph,q3_dph,q4_dph\n",
    );
    for k in 0..6 {
        let r = 10.0 * (k as f64).cos();
        text += &format!("{k},{},{},{r},{r},{r},{r},{r}\n", k + 1, 60 * k);
    }
    let r = Recording::parse(&text).unwrap();
    assert!(r.rows.iter().all(|row| row.quarters_dph.is_none()));
    assert!(
        r.warnings
            .iter()
            .any(|w| w.line == 4 && w.what.contains("equal to one another in all 6 dwells")),
        "{:?}",
        r.warnings
    );
    // One dwell whose quarters differ: they are quarters, and every row keeps its own.
    let varied = text.replacen(",1,0,10,10,10,10,10\n", ",1,0,10,9.9,10.1,10,10\n", 1);
    assert_ne!(varied, text);
    let r = Recording::parse(&varied).unwrap();
    assert!(r.rows.iter().all(|row| row.quarters_dph.is_some()), "{:?}", r.warnings);
}

#[test]
fn quarters_of_fewer_than_four_samples_are_not_quarters() {
    // Six dwells of 100 samples with quarters, the third of `few` samples.
    let text = |few: u32| {
        let mut text = String::from(
            "# format = northfinder-recording/1\n# latitude_deg = 45\nindex,t_s,encoder_deg,rate_dph,samples,q1_dph,q2_dph,q3_dph,q4_dph\n",
        );
        for k in 0..6 {
            let r = 10.0 * (k as f64).cos();
            let samples = if k == 2 { few } else { 100 };
            text += &format!(
                "{k},{},{},{r},{samples},{},{},{r},{r}\n",
                k + 1,
                60 * k,
                r - 0.01,
                r + 0.01
            );
        }
        text
    };
    let r = Recording::parse(&text(3)).unwrap();
    let kept: Vec<bool> = r.rows.iter().map(|row| row.quarters_dph.is_some()).collect();
    assert_eq!(kept, [true, true, false, true, true, true]);
    assert!(
        r.warnings
            .iter()
            .any(|w| w.line == 6 && w.what.contains("1 dwell(s) of fewer than 4 samples (samples 3)")),
        "{:?}",
        r.warnings
    );
    let r = Recording::parse(&text(4)).unwrap();
    assert!(r.rows.iter().all(|row| row.quarters_dph.is_some()), "{:?}", r.warnings);
    assert!(r.warnings.is_empty(), "{:?}", r.warnings);
}

#[test]
fn a_sample_spread_of_zero_over_many_samples_is_said() {
    let mut text = String::from(
        "# format = northfinder-recording/1\n# latitude_deg = 45\nindex,t_s,encoder_deg,rate_dph,rate_sd_dph,samples\n",
    );
    for k in 0..6 {
        let (sd, samples) = match k {
            3 | 4 => (0.0, 100),
            5 => (0.0, 1),
            _ => (0.2, 100),
        };
        text += &format!("{k},{},{},{},{sd},{samples}\n", k + 1, 60 * k, 10.0 * (k as f64).cos());
    }
    let r = Recording::parse(&text).unwrap();
    let said: Vec<_> = r
        .warnings
        .iter()
        .filter(|w| w.what.contains("rate_sd_dph is 0"))
        .collect();
    assert_eq!(said.len(), 1, "{:?}", r.warnings);
    assert!(
        said[0].line == 7 && said[0].what.contains("in 2 dwell(s)"),
        "{:?}",
        said
    );
    assert_eq!(r.rows[3].rate_sd_dph, Some(0.0), "kept as written");
}

#[test]
fn a_second_header_is_two_files_joined_and_a_long_bad_cell_is_cut() {
    let joined = format!("{HEAD}0,1,0,1\nindex,t_s,encoder_deg,rate_dph\n1,2,90,0\n");
    assert_eq!(
        error(&joined),
        (
            5,
            "line 5: the header of line 3 again: two files joined? Each file holds one run".into()
        )
    );
    let junk: String = "\u{7}\u{1b}[2J".repeat(30);
    let (line, what) = error(&format!("{HEAD}{junk},1,0,1\n"));
    assert_eq!(line, 4);
    assert!(what.contains("... (150 bytes)' is not a finite number"), "{what}");
    assert!(!what.contains('\u{1b}') && what.len() < 120, "{what}");
}

#[test]
fn some_of_the_quarter_columns_and_times_before_the_start_are_said() {
    let text = "# format = northfinder-recording/1\n# latitude_deg = 1\nindex,t_s,encoder_deg,rate_dph,q1_dph,q2_dph\n0,-5,0,1,1,1\n1,-2,90,1,1,1\n2,1,180,1,1,1\n";
    let r = Recording::parse(text).unwrap();
    let said: Vec<String> = r.warnings.iter().map(|w| w.to_string()).collect();
    assert_eq!(
        said,
        [
            "line 3: q1_dph, q2_dph without the other quarter columns: a dwell's quarters are read only as all four (q1_dph .. q4_dph), so these are not used",
            "line 4: t_s -5 is before the run's start, from which the format counts it (2 such dwell(s)); the times are used as given",
        ]
    );
    assert!(r.rows.iter().all(|r| r.quarters_dph.is_none()));
    assert_eq!(r.rows[0].t_s, -5.0);
}

#[test]
fn a_leap_in_time_is_said_with_its_lines() {
    let run = |last: &str| {
        let mut text =
            String::from("# format = northfinder-recording/1\n# latitude_deg = 1\nindex,t_s,encoder_deg,rate_dph\n");
        for k in 0..7 {
            text += &format!("{k},{},{},1\n", 2 * k, 45 * k);
        }
        Recording::parse(&format!("{text}7,{last},315,1\n")).unwrap()
    };
    let said: Vec<String> = run("1e300").warnings.iter().map(|w| w.to_string()).collect();
    assert_eq!(said.len(), 1, "{said:?}");
    assert!(
        said[0].starts_with(
            "line 11: t_s leaps by 1.0000e300 s from line 10 (the median step between visits is 2 s; 1 such leap(s))"
        ),
        "{said:?}"
    );
    // A half turn's longer step says nothing.
    assert!(run("15").warnings.is_empty());
}

#[test]
fn a_run_that_ended_before_its_planned_positions_is_said_to() {
    // The firmware writes the positions it plans; an early stop leaves fewer rows.
    let planned = |v: &str| GOOD.replace("# instrument", &format!("# positions = {v}\n# instrument"));
    let r = Recording::parse(&planned("72")).unwrap();
    let said: Vec<&str> = r.warnings.iter().map(|w| w.what.as_str()).collect();
    assert!(
        r.warnings
            .iter()
            .any(|w| w.line == 3 && w.what.starts_with("positions = 72 but 4 rows: the run ended")),
        "{said:?}"
    );
    assert_eq!(r.rows.len(), 4);
    // All of them written, or a key of another writer's: nothing to say.
    for v in ["4", "four"] {
        let r = Recording::parse(&planned(v)).unwrap();
        assert!(
            r.warnings.iter().all(|w| !w.what.contains("positions")),
            "{:?}",
            r.warnings
        );
    }
}

//! The class report, on a class of 30 generated students: the counts, shares, medians and
//! wrong answers it reports are the ones the class's files hold; damaged and foreign files
//! are named and left out; files from before tries were kept still read.

use super::*;
use crate::level::{Progress, utc_time};

/// Student `k`'s answers to the trilinear level's P2 question (true value 4.988): every third
/// student is right at once; the others first answer 5.0 (k even) or 4.9, then right, after
/// 30 + k seconds.
fn student(k: usize) -> Progress {
    let mut p = Progress::default();
    let q = "the value at (0.5, 0.5, 0.5)";
    let mut answer = |said: &str, correct: bool, attempt: u32, seconds: f64| {
        p.answers.push(Answer {
            level: "trilinear".into(),
            step: 2,
            question: q.into(),
            answer: said.into(),
            expected: "4.988".into(),
            correct,
            at: 1_796_464_427 + k as u64 * 60 + u64::from(attempt),
            run: None,
            attempt: Some(attempt),
            seconds: Some(seconds),
        });
    };
    if k.is_multiple_of(3) {
        answer("4.99", true, 1, 20.0);
    } else {
        answer(
            if k.is_multiple_of(2) { "5.0" } else { "4,9" },
            false,
            1,
            15.0,
        );
        answer("4.988", true, 2, 30.0 + k as f64);
    }
    // Half of them also named trace 4's effect, wrongly first where k is odd.
    if k % 2 == 1 {
        p.answers.push(Answer {
            level: "which-effect".into(),
            step: 3,
            question: "which effect cast trace 4".into(),
            answer: "reflection rays".into(),
            expected: "shadow rays".into(),
            correct: false,
            at: 1_796_464_427,
            run: None,
            attempt: Some(1),
            seconds: Some(5.0),
        });
    }
    p
}

/// The class's 30 files: 27 written today, 1 written before tries were kept (its last two
/// columns cut), a damaged one and a foreign one.
fn class() -> Vec<Handed> {
    let mut files: Vec<Handed> = (0..28)
        .map(|k| {
            let mut text = student(k).answers_csv();
            if k == 27 {
                text = text
                    .lines()
                    .map(|l| {
                        let cut: Vec<&str> = l.rsplitn(3, ',').collect();
                        format!("{}\n", cut[2])
                    })
                    .collect();
            }
            Handed {
                name: format!("student{k:02}.csv"),
                text,
            }
        })
        .collect();
    let damaged = student(0).answers_csv().replace(",yes,", ",perhaps,");
    files.push(Handed {
        name: "damaged.csv".into(),
        text: damaged,
    });
    files.push(Handed {
        name: "grades.csv".into(),
        text: "name,grade\nAda,A\n".into(),
    });
    files
}

#[test]
fn a_class_of_thirty_becomes_one_report() {
    let report = class_report(&class());
    assert_eq!(report.read.len(), 28);
    let left: Vec<&str> = report.left_out.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(left, ["damaged.csv", "grades.csv"]);
    assert!(
        report.left_out[0]
            .1
            .contains("line 2: correct is neither yes nor no")
    );
    assert!(report.left_out[1].1.contains("not a Voxcast answers file"));
    // Built-in levels in teaching order: trilinear before which-effect.
    let [p2, effect] = &report.steps[..] else {
        panic!("{:#?}", report.steps)
    };
    assert_eq!((p2.level.as_str(), p2.step), ("trilinear", 2));
    assert_eq!(p2.students, 28);
    let right_at_once = (0usize..28).filter(|k| k.is_multiple_of(3)).count();
    assert_eq!((p2.right_first, p2.right_in_the_end), (right_at_once, 28));
    // Tries: 1 for 10 students, 2 for 18: the median is 2.
    assert_eq!(p2.median_tries, Some(2.0));
    // Seconds of the right answer: 20 (×10) and 30 + k for the rest (k = 1, 2, 4, 5, …, 26,
    // and 27 is the old file, whose times are unknown): the median of the 27 known.
    let mut known: Vec<f64> = (0usize..27)
        .map(|k| {
            if k.is_multiple_of(3) {
                20.0
            } else {
                30.0 + k as f64
            }
        })
        .collect();
    known.sort_by(f64::total_cmp);
    assert_eq!(p2.median_seconds, Some(known[13]));
    // Wrong answers grouped as numbers: "4,9" and "4.9" alike.
    let evens = (0usize..28)
        .filter(|k| !k.is_multiple_of(3) && k.is_multiple_of(2))
        .count();
    let odds = (0usize..28)
        .filter(|k| !k.is_multiple_of(3) && k % 2 == 1)
        .count();
    assert_eq!(p2.wrong, [("4.9".into(), odds), ("5".into(), evens)]);
    assert_eq!(
        (effect.students, effect.right_first, effect.right_in_the_end),
        (14, 0, 0)
    );
    assert_eq!(effect.median_tries, None);
    let titles = vec![(
        "trilinear".to_string(),
        "Trilinear <interpolation>".to_string(),
    )];
    let html = class_html(&report, &titles);
    assert!(
        html.contains("Trilinear &lt;interpolation&gt;"),
        "titles escaped"
    );
    assert!(html.contains("28 answer files read, 2 left out"));
    assert_eq!(html.matches("<svg").count(), 2, "a chart per level");
    assert!(html.contains(&format!("{right_at_once} (36%)")));
    assert!(html.contains("4.9 ×9, 5 ×9"), "{html}");
}

#[test]
fn answers_files_read_back_as_written() {
    let p = student(1);
    assert_eq!(read_answers_csv(&p.answers_csv()).unwrap(), p.answers);
    // Quotes, commas and line breaks inside fields, and CRLF line ends.
    let mut q = student(3);
    q.answers[0].answer = "4,9 \"or so\"\nI think".into();
    assert_eq!(read_answers_csv(&q.answers_csv()).unwrap(), q.answers);
    let crlf = p.answers_csv().replace('\n', "\r\n");
    assert_eq!(read_answers_csv(&crlf).unwrap(), p.answers);
    for bad in ["", "level,step\n", "\"unclosed"] {
        assert!(read_answers_csv(bad).is_err(), "{bad:?}");
    }
    for (s, iso) in [
        (0, "1970-01-01T00:00:00Z"),
        (951_782_400, "2000-02-29T00:00:00Z"),
        (1_796_464_427, "2026-12-05T09:53:47Z"),
    ] {
        assert_eq!(utc_time(s), iso);
        assert_eq!(parse_utc(iso), Some(s));
    }
    assert_eq!(parse_utc("2026-13-01T00:00:00Z"), None);
}

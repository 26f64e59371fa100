//! A class's answers read together: the answers' CSV files a class hands in (one a student,
//! as the levels panel's Export and `voxcast answers` write them, old and new) become one
//! report — per level and step, how many students answered, the share right at their first
//! try and in the end, the median tries and time to the right answer, the commonest wrong
//! answers — written as one HTML file with a bar chart per level (SVG inside it, so it opens
//! in any browser, offline). A damaged or foreign file is named in the report and left out.

use super::progress::{Answer, CSV_HEADER};
use crate::numbers::sig;

/// The columns of an answers file written before tries and times were kept.
const OLD_HEADER: &str = "level,step,question,answer,expected,correct,time (UTC),run";

/// Reads an answers file (as [`super::Progress::answers_csv`] writes it, or the older one
/// without `try` and `seconds`): every answer, or what is wrong with the file.
pub fn read_answers_csv(text: &str) -> Result<Vec<Answer>, String> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let rows = csv_rows(text)?;
    let Some((header, body)) = rows.split_first() else {
        return Err("it is empty".into());
    };
    let header = header.join(",");
    let new = header == CSV_HEADER;
    if !new && header != OLD_HEADER {
        return Err(format!(
            "not a Voxcast answers file: its first line is “{}”",
            shorten(&header, 60)
        ));
    }
    let columns = if new { 10 } else { 8 };
    let mut answers = Vec::with_capacity(body.len());
    for (i, row) in body.iter().enumerate() {
        let line = i + 2;
        if row.len() == 1 && row[0].is_empty() {
            continue;
        }
        if row.len() != columns {
            return Err(format!(
                "line {line} has {} fields where the header has {columns}",
                row.len()
            ));
        }
        let bad = |what: &str, v: &str| format!("line {line}: {what} “{}”", shorten(v, 30));
        let step = row[1]
            .parse()
            .map_err(|_| bad("the step is not a number:", &row[1]))?;
        let correct = match row[5].as_str() {
            "yes" => true,
            "no" => false,
            other => return Err(bad("correct is neither yes nor no:", other)),
        };
        let at = parse_utc(&row[6]).ok_or_else(|| bad("the time is not a UTC time:", &row[6]))?;
        let optional = |i: usize| row.get(i).filter(|v| !v.is_empty());
        let attempt = match optional(8) {
            Some(v) => Some(v.parse().map_err(|_| bad("the try is not a number:", v))?),
            None => None,
        };
        let seconds = match optional(9) {
            Some(v) => Some(
                v.parse::<f64>()
                    .ok()
                    .filter(|s| s.is_finite() && *s >= 0.0)
                    .ok_or_else(|| bad("the seconds are not a time:", v))?,
            ),
            None => None,
        };
        answers.push(Answer {
            level: row[0].clone(),
            step,
            question: row[2].clone(),
            answer: row[3].clone(),
            expected: row[4].clone(),
            correct,
            at,
            run: optional(7).cloned(),
            attempt,
            seconds,
        });
    }
    Ok(answers)
}

fn shorten(s: &str, n: usize) -> String {
    match s.char_indices().nth(n) {
        Some((i, _)) => format!("{}…", &s[..i]),
        None => s.to_string(),
    }
}

/// The rows of a CSV text (RFC 4180: quoted fields may hold commas, quotes doubled, and line
/// breaks; a line may end in CRLF).
fn csv_rows(text: &str) -> Result<Vec<Vec<String>>, String> {
    let mut rows = Vec::new();
    let mut row = Vec::new();
    let mut field = String::new();
    let mut quoted = false;
    let mut chars = text.chars().peekable();
    let mut line = 1;
    while let Some(c) = chars.next() {
        match (quoted, c) {
            (true, '"') if chars.peek() == Some(&'"') => {
                field.push('"');
                chars.next();
            }
            (true, '"') => quoted = false,
            (true, c) => {
                line += usize::from(c == '\n');
                field.push(c);
            }
            (false, '"') if field.is_empty() => quoted = true,
            (false, ',') => row.push(std::mem::take(&mut field)),
            (false, '\r') if chars.peek() == Some(&'\n') => {}
            (false, '\n') => {
                row.push(std::mem::take(&mut field));
                rows.push(std::mem::take(&mut row));
                line += 1;
            }
            (false, c) => field.push(c),
        }
    }
    if quoted {
        return Err(format!("a quote opened on line {line} is never closed"));
    }
    if !field.is_empty() || !row.is_empty() {
        row.push(field);
        rows.push(row);
    }
    Ok(rows)
}

/// `2026-12-04T09:53:47Z` as seconds since 1970 (the inverse of [`super::utc_time`]).
pub fn parse_utc(s: &str) -> Option<u64> {
    let b = s.as_bytes();
    if b.len() != 20 || b[4] != b'-' || b[7] != b'-' || b[10] != b'T' || b[19] != b'Z' {
        return None;
    }
    let n = |r: std::ops::Range<usize>| s.get(r)?.parse::<i64>().ok();
    let (y, m, d) = (n(0..4)?, n(5..7)?, n(8..10)?);
    let (h, mi, sec) = (n(11..13)?, n(14..16)?, n(17..19)?);
    if !(1..=12).contains(&m) || !(1..=31).contains(&d) || h > 23 || mi > 59 || sec > 60 {
        return None;
    }
    // Howard Hinnant's days-from-civil.
    let y = y - i64::from(m <= 2);
    let era = y.div_euclid(400);
    let yoe = y - era * 400;
    let mp = (m + 9) % 12;
    let doy = (153 * mp + 2) / 5 + d - 1;
    let doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    let days = era * 146_097 + doe - 719_468;
    u64::try_from(days * 86_400 + h * 3_600 + mi * 60 + sec).ok()
}

/// One student's file, as handed in.
pub struct Handed {
    /// The file's name (the student, as the teacher named the file).
    pub name: String,
    pub text: String,
}

/// What the class answered to one question of one step.
#[derive(Clone, Debug, PartialEq)]
pub struct StepReport {
    pub level: String,
    pub step: usize,
    pub question: String,
    /// A study's run, where the answers came from one.
    pub run: Option<String>,
    /// Students who answered it at all.
    pub students: usize,
    /// …right at their first try, and right at some try.
    pub right_first: usize,
    pub right_in_the_end: usize,
    /// Among those right in the end: the median number of tries, and of seconds from the
    /// step's opening to the right answer (where the file kept them).
    pub median_tries: Option<f64>,
    pub median_seconds: Option<f64>,
    /// The commonest wrong answers (numbers to four significant digits), most frequent first.
    pub wrong: Vec<(String, usize)>,
}

/// A class's report: the files read, those left out and why, and each step's answers.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct ClassReport {
    pub read: Vec<String>,
    pub left_out: Vec<(String, String)>,
    pub steps: Vec<StepReport>,
}

/// How many wrong answers a step lists.
const WRONG_LISTED: usize = 3;

/// Reads every handed file and gathers the class's answers, step by step.
pub fn class_report(files: &[Handed]) -> ClassReport {
    let mut report = ClassReport::default();
    let mut students: Vec<(String, Vec<Answer>)> = Vec::new();
    for f in files {
        match read_answers_csv(&f.text) {
            Ok(answers) if answers.is_empty() => report
                .left_out
                .push((f.name.clone(), "it holds no answers".into())),
            Ok(answers) => {
                report.read.push(f.name.clone());
                students.push((f.name.clone(), answers));
            }
            Err(e) => report.left_out.push((f.name.clone(), e)),
        }
    }
    // Each question in the order it was first met.
    type Key = (String, usize, String, Option<String>);
    let mut keys: Vec<Key> = Vec::new();
    for (_, answers) in &students {
        for a in answers {
            let key = (a.level.clone(), a.step, a.question.clone(), a.run.clone());
            if !keys.contains(&key) {
                keys.push(key);
            }
        }
    }
    keys.sort_by(|a, b| {
        let order = |id: &str| super::Level::all().iter().position(|l| l.id == id);
        (order(&a.0).unwrap_or(usize::MAX), &a.0, a.1, &a.3, &a.2).cmp(&(
            order(&b.0).unwrap_or(usize::MAX),
            &b.0,
            b.1,
            &b.3,
            &b.2,
        ))
    });
    for (level, step, question, run) in keys {
        let mut s = StepReport {
            level: level.clone(),
            step,
            question: question.clone(),
            run: run.clone(),
            students: 0,
            right_first: 0,
            right_in_the_end: 0,
            median_tries: None,
            median_seconds: None,
            wrong: Vec::new(),
        };
        let (mut tries, mut seconds) = (Vec::new(), Vec::new());
        let mut wrong: Vec<(String, usize)> = Vec::new();
        for (_, answers) in &students {
            let mine: Vec<&Answer> = answers
                .iter()
                .filter(|a| {
                    a.level == level && a.step == step && a.question == question && a.run == run
                })
                .collect();
            if mine.is_empty() {
                continue;
            }
            s.students += 1;
            s.right_first += usize::from(mine[0].correct);
            if let Some(k) = mine.iter().position(|a| a.correct) {
                s.right_in_the_end += 1;
                tries.push((k + 1) as f64);
                seconds.extend(mine[k].seconds);
            }
            for a in mine.iter().filter(|a| !a.correct) {
                let said = said(&a.answer);
                match wrong.iter_mut().find(|(w, _)| *w == said) {
                    Some((_, n)) => *n += 1,
                    None => wrong.push((said, 1)),
                }
            }
        }
        wrong.sort_by(|a, b| b.1.cmp(&a.1).then_with(|| a.0.cmp(&b.0)));
        wrong.truncate(WRONG_LISTED);
        s.wrong = wrong;
        s.median_tries = crate::numbers::median(&tries);
        s.median_seconds = crate::numbers::median(&seconds);
        report.steps.push(s);
    }
    report
}

/// An answer as the report groups it: a number to four significant digits (a decimal comma
/// read as a point), else the words, trimmed and in lower case.
fn said(answer: &str) -> String {
    let t = answer.trim();
    match t.replace(',', ".").parse::<f64>() {
        Ok(v) if v.is_finite() => sig(v as f32),
        _ => t.to_lowercase(),
    }
}

/// Text made safe inside HTML.
fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// A share as a whole percentage.
fn percent(n: usize, of: usize) -> String {
    if of == 0 {
        "–".into()
    } else {
        format!("{}%", (100.0 * n as f64 / of as f64).round())
    }
}

/// A duration a teacher reads: seconds under two minutes, else minutes.
fn duration(s: f64) -> String {
    if s < 120.0 {
        format!("{} s", s.round())
    } else {
        format!("{} min", (s / 60.0 * 10.0).round() / 10.0)
    }
}

/// The report as one HTML file: a summary of the files, then per level a bar chart (share
/// right at the first try and in the end, per step) and a table. `titles` names the levels
/// (id → title); an unknown id stands as it is.
pub fn class_html(report: &ClassReport, titles: &[(String, String)]) -> String {
    let title = |id: &str| {
        titles
            .iter()
            .find(|(i, _)| i == id)
            .map_or_else(|| id.to_string(), |(_, t)| t.clone())
    };
    let mut html = String::from(
        "<!doctype html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <title>Voxcast: a class's answers</title>\n<style>\n\
         body { font: 15px/1.45 system-ui, sans-serif; margin: 2em auto; max-width: 60em; \
         color: #222; padding: 0 1em; }\n\
         table { border-collapse: collapse; margin: 0.5em 0 2em; }\n\
         th, td { border-bottom: 1px solid #ddd; padding: 0.3em 0.7em; text-align: left; \
         vertical-align: top; }\n th { background: #f3f3f3; }\n\
         .num { text-align: right; } .note { color: #666; } .bad { color: #a33; }\n\
         svg { display: block; margin: 0.5em 0; }\n</style>\n</head>\n<body>\n\
         <h1>A class's answers</h1>\n",
    );
    html += &format!(
        "<p>{} answer file{} read{}. A student is one file; a try is one answer checked; \
         the first try counts. Times run from the step's opening to the right answer.</p>\n",
        report.read.len(),
        if report.read.len() == 1 { "" } else { "s" },
        if report.left_out.is_empty() {
            String::new()
        } else {
            format!(", {} left out", report.left_out.len())
        }
    );
    if !report.left_out.is_empty() {
        html += "<p class=\"bad\">Left out:</p>\n<ul class=\"bad\">\n";
        for (name, why) in &report.left_out {
            html += &format!("<li>{}: {}</li>\n", esc(name), esc(why));
        }
        html += "</ul>\n";
    }
    if report.steps.is_empty() {
        html += "<p>No answers to report.</p>\n";
    }
    let mut levels: Vec<&str> = Vec::new();
    for s in &report.steps {
        if !levels.contains(&s.level.as_str()) {
            levels.push(&s.level);
        }
    }
    for level in levels {
        let steps: Vec<&StepReport> = report.steps.iter().filter(|s| s.level == level).collect();
        html += &format!(
            "<h2>{} <span class=\"note\">({})</span></h2>\n",
            esc(&title(level)),
            esc(level)
        );
        html += &chart(&steps);
        html += "<table>\n<tr><th>step</th><th>question</th><th class=\"num\">students</th>\
                 <th class=\"num\">right at the first try</th><th class=\"num\">right in the \
                 end</th><th class=\"num\">median tries</th><th class=\"num\">median time</th>\
                 <th>commonest wrong answers</th></tr>\n";
        for s in steps {
            let wrong: Vec<String> = s
                .wrong
                .iter()
                .map(|(w, n)| format!("{} ×{n}", esc(w)))
                .collect();
            html += &format!(
                "<tr><td>{}{}</td><td>{}</td><td class=\"num\">{}</td><td class=\"num\">{} \
                 ({})</td><td class=\"num\">{} ({})</td><td class=\"num\">{}</td>\
                 <td class=\"num\">{}</td><td>{}</td></tr>\n",
                s.step,
                s.run
                    .as_ref()
                    .map(|r| format!(" <span class=\"note\">({})</span>", esc(r)))
                    .unwrap_or_default(),
                esc(&s.question),
                s.students,
                s.right_first,
                percent(s.right_first, s.students),
                s.right_in_the_end,
                percent(s.right_in_the_end, s.students),
                s.median_tries.map_or("–".into(), |t| format!("{t}")),
                s.median_seconds.map_or("–".into(), duration),
                if wrong.is_empty() {
                    "–".into()
                } else {
                    wrong.join(", ")
                },
            );
        }
        html += "</table>\n";
    }
    html +=
        "<p class=\"note\">Written by Voxcast (voxcast answers --class).</p>\n</body>\n</html>\n";
    html
}

/// A level's bar chart: per step, the share of its students right at the first try (dark)
/// and in the end (light), 0 to 100 %.
fn chart(steps: &[&StepReport]) -> String {
    let (bar, gap, left, top, height) = (18.0, 22.0, 44.0, 12.0, 160.0);
    let group = 2.0 * bar + gap;
    // Wide enough for the legend under a level of one or two steps.
    let width = (left + group * steps.len() as f64 + gap).max(left + 300.0);
    let total_height = top + height + 44.0;
    let mut svg = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width}\" height=\"{total_height}\" \
         role=\"img\" aria-label=\"share right per step\" font-family=\"system-ui, sans-serif\" \
         font-size=\"11\">\n"
    );
    for pct in [0, 25, 50, 75, 100] {
        let y = top + height * (1.0 - f64::from(pct) / 100.0);
        svg += &format!(
            "<line x1=\"{left}\" x2=\"{width}\" y1=\"{y}\" y2=\"{y}\" stroke=\"#ddd\"/>\
             <text x=\"{}\" y=\"{}\" text-anchor=\"end\">{pct}%</text>\n",
            left - 4.0,
            y + 4.0
        );
    }
    for (i, s) in steps.iter().enumerate() {
        let x = left + gap + group * i as f64;
        for (k, (n, colour, what)) in [
            (s.right_first, "#2c5aa0", "right at the first try"),
            (s.right_in_the_end, "#9fbfe8", "right in the end"),
        ]
        .into_iter()
        .enumerate()
        {
            let share = if s.students == 0 {
                0.0
            } else {
                n as f64 / s.students as f64
            };
            let h = height * share;
            svg += &format!(
                "<rect x=\"{}\" y=\"{}\" width=\"{bar}\" height=\"{h}\" fill=\"{colour}\">\
                 <title>step {}: {} of {} {what}</title></rect>\n",
                x + bar * k as f64,
                top + height - h,
                s.step,
                n,
                s.students
            );
        }
        svg += &format!(
            "<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">step {}</text>\n",
            x + bar,
            top + height + 14.0,
            s.step
        );
    }
    svg += &format!(
        "<rect x=\"{left}\" y=\"{}\" width=\"10\" height=\"10\" fill=\"#2c5aa0\"/>\
         <text x=\"{}\" y=\"{}\">right at the first try</text>\
         <rect x=\"{}\" y=\"{}\" width=\"10\" height=\"10\" fill=\"#9fbfe8\"/>\
         <text x=\"{}\" y=\"{}\">right in the end</text>\n</svg>\n",
        top + height + 24.0,
        left + 14.0,
        top + height + 33.0,
        left + 150.0,
        top + height + 24.0,
        left + 164.0,
        top + height + 33.0,
    );
    svg
}

#[cfg(test)]
mod tests;

//! The firing-order study's outputs (`enginedyn firing-orders`,
//! INTERFACE.md): the printed table, `--json`, `firing_orders.csv` and the
//! crank end view `crank_end_view.svg`. The study is `enginedyn_balance`'s;
//! this module only writes it.

use crate::{Chart, Figure, Series};
use enginedyn_balance::{CrankStudy, FreeForces, OrderStudy, Study, Weights};
use enginedyn_engine::{Engine, Layout};
use serde_json::{Value, json};
use std::fmt::Write as _;

/// What `firing-orders --out DIR` writes.
pub const FIRING_FILES: [&str; 2] = ["firing_orders.csv", "crank_end_view.svg"];

/// What `firing-orders --json` prints: with `all` every crank
/// (`{"cranks": [...], "notes": [...]}`), else the engine's crank with the
/// notes beside its fields.
pub fn firing_json(s: &Study, all: bool) -> Value {
    if all {
        json!({
            "cranks": s.cranks.iter().map(crank_json).collect::<Vec<_>>(),
            "notes": s.notes,
        })
    } else {
        let mut doc = s
            .cranks
            .first()
            .map(crank_json)
            .unwrap_or_else(|| json!({}));
        if let Value::Object(m) = &mut doc {
            m.insert("notes".into(), json!(s.notes));
        }
        doc
    }
}

fn free_json(f: &FreeForces) -> Value {
    json!({
        "free_force_1_n": f.free_force_1_n,
        "free_force_2_n": f.free_force_2_n,
        "free_moment_1_nm": f.free_moment_1_nm,
        "free_moment_2_nm": f.free_moment_2_nm,
        "free_moment_1_residual_nm": f.free_moment_1_residual_nm,
    })
}

fn crank_json(c: &CrankStudy) -> Value {
    json!({
        "crank_angles_deg": c.crank_angles_deg,
        "free_forces": free_json(&c.free),
        "orders": c.orders.iter().map(order_json).collect::<Vec<_>>(),
        "mirror_symmetric": c.mirror_symmetric,
        "engine_crank": c.engine_crank,
    })
}

fn order_json(o: &OrderStudy) -> Value {
    let c = &o.criteria;
    let j = o.journal.as_ref();
    json!({
        "firing_order": o.order.order,
        "intervals_deg": c.intervals_deg,
        "neighbour_consecutive": c.neighbour_consecutive,
        "max_journal_torque_nm": j.map(|j| j.max_torque_nm),
        "max_journal_harmonic_nm": j.map(|j| j.max_harmonic_nm),
        "journal_harmonic_order": j.map(|j| j.harmonic_order),
        "score": o.score,
        "firing_angles_deg": o.order.angles_deg,
        "bank_intervals_deg": c.bank_intervals_deg,
        "scheme": c.scheme.map(|s| s.name()),
        "neighbour_pairs": c.neighbour_pairs.iter().map(|&(a, b)| [a, b]).collect::<Vec<_>>(),
        "journal_most_loaded": j.map(|j| j.max_torque_journal),
        "score_terms": {
            "intervals": o.terms.intervals,
            "neighbours": o.terms.neighbours,
            "journal": j.map(|_| o.terms.journal),
            "balance": o.terms.balance,
        },
    })
}

/// `a-b-c` for a list of numbers (shortest round-trip form).
fn dashed<T: std::fmt::Display>(v: &[T]) -> String {
    v.iter()
        .map(|x| x.to_string())
        .collect::<Vec<_>>()
        .join("-")
}

fn banks(iv: &[Vec<f64>]) -> String {
    iv.iter().map(|b| dashed(b)).collect::<Vec<_>>().join(" | ")
}

fn opt(v: Option<f64>, digits: usize) -> String {
    v.map_or_else(|| "null".to_string(), |x| format!("{x:.digits$}"))
}

/// The printed table: the heading and the score's weights, then for one
/// crank its free forces and its orders ranked (with a legend), or with
/// `all` every crank with its best order; the study's notes last.
pub fn firing_table(
    engine: &Engine,
    shown: &str,
    rpm: f64,
    w: &Weights,
    s: &Study,
    all: bool,
) -> String {
    let mut o = crate::heading(engine, "", rpm, shown);
    let _ = writeln!(
        o,
        "score (lower is better) = {} × intervals + {} × neighbours + {} × journal + {} × balance",
        w.intervals, w.neighbours, w.journal, w.balance
    );
    if all {
        cranks_table(&mut o, &s.cranks);
    } else if let Some(c) = s.cranks.first() {
        let _ = writeln!(
            o,
            "crank: {} (throw lags, deg)",
            dashed(&c.crank_angles_deg)
        );
        free_forces_lines(&mut o, &c.free);
        let two_banks = !matches!(engine.layout(), Layout::Inline);
        orders_table(&mut o, &c.orders, two_banks);
        let journals = c.orders.iter().any(|x| x.journal.is_some());
        let _ = write!(o, "\n{}", legend(two_banks, journals));
    }
    for n in &s.notes {
        let _ = writeln!(o, "note: {n}");
    }
    o
}

/// `--all-cranks`' table: every crank ranked, marked when it is the
/// engine's or mirror-symmetric, with its free forces and best order.
fn cranks_table(o: &mut String, cranks: &[CrankStudy]) {
    let marked = |c: &CrankStudy| {
        let mark = match (c.engine_crank, c.mirror_symmetric) {
            (true, _) => " (engine's)",
            (false, true) => " (mirror)",
            _ => "",
        };
        format!("{}{mark}", dashed(&c.crank_angles_deg))
    };
    let wc = cranks
        .iter()
        .map(|c| marked(c).chars().count())
        .chain([23])
        .max()
        .unwrap_or(23);
    let wo = cranks
        .iter()
        .filter_map(|c| c.orders.first())
        .map(|b| dashed(&b.order.order).len())
        .chain([10])
        .max()
        .unwrap_or(10);
    let _ = writeln!(
        o,
        "\n{:>4}  {:<wc$} {:>6} {:>10} {:>10} {:>10} {:>10} {:>10}  {:<wo$} {:>8}",
        "rank",
        "crank (throw lags, deg)",
        "orders",
        "F1 N",
        "F2 N",
        "M1 N m",
        "M2 N m",
        "M1 cw N m",
        "best order",
        "score"
    );
    for (k, c) in cranks.iter().enumerate() {
        let f = &c.free;
        let best = c.orders.first();
        let _ = writeln!(
            o,
            "{:>4}  {:<wc$} {:>6} {:>10.1} {:>10.1} {:>10.1} {:>10.1} {:>10.1}  {:<wo$} {:>8.4}",
            k + 1,
            marked(c),
            c.orders.len(),
            f.free_force_1_n,
            f.free_force_2_n,
            f.free_moment_1_nm,
            f.free_moment_2_nm,
            f.free_moment_1_residual_nm,
            best.map_or(String::new(), |b| dashed(&b.order.order)),
            c.best_score()
        );
    }
}

/// One crank's free forces and moments of the reciprocating masses.
fn free_forces_lines(o: &mut String, f: &FreeForces) {
    let _ = writeln!(
        o,
        "\nfree forces of the reciprocating masses (before counterweights; the same for every order)"
    );
    for (label, v, unit) in [
        ("first-order force", f.free_force_1_n, "N"),
        ("second-order force", f.free_force_2_n, "N"),
        ("first-order moment", f.free_moment_1_nm, "N m"),
        ("second-order moment", f.free_moment_2_nm, "N m"),
        (
            "first-order moment after counterweights",
            f.free_moment_1_residual_nm,
            "N m",
        ),
    ] {
        let _ = writeln!(o, "  {label:<42} {v:>12.2} {unit}");
    }
}

/// One crank's firing orders ranked: intervals (per bank and the banks'
/// scheme with `two_banks`), neighbours, journal torques, score.
fn orders_table(o: &mut String, orders: &[OrderStudy], two_banks: bool) {
    let wo = orders
        .iter()
        .map(|x| dashed(&x.order.order).len())
        .chain([12])
        .max()
        .unwrap_or(12);
    let wb = orders
        .iter()
        .map(|x| banks(&x.criteria.bank_intervals_deg).len())
        .chain([20])
        .max()
        .unwrap_or(20);
    let ws = if two_banks { 17 } else { 0 };
    // An inline engine's one bank: its intervals are the engine's.
    let intervals = if two_banks {
        "bank intervals (deg)"
    } else {
        "intervals (deg)"
    };
    let _ = writeln!(
        o,
        "\n{:>4}  {:<wo$} {:<ws$} {:<wb$} {:>10} {:>12} {:>11} {:>12} {:>6} {:>8}",
        "rank",
        "firing order",
        if two_banks { "scheme" } else { "" },
        intervals,
        "neighbours",
        "journal N m",
        "after throw",
        "harmonic N m",
        "order",
        "score"
    );
    for (k, ord) in orders.iter().enumerate() {
        let cr = &ord.criteria;
        let j = ord.journal.as_ref();
        let _ = writeln!(
            o,
            "{:>4}  {:<wo$} {:<ws$} {:<wb$} {:>10} {:>12} {:>11} {:>12} {:>6} {:>8.4}",
            k + 1,
            dashed(&ord.order.order),
            cr.scheme.map_or("", |s| s.name()),
            banks(&cr.bank_intervals_deg),
            cr.neighbour_consecutive,
            opt(j.map(|j| j.max_torque_nm), 1),
            j.map_or_else(|| "null".to_string(), |j| j.max_torque_journal.to_string()),
            opt(j.map(|j| j.max_harmonic_nm), 1),
            opt(j.map(|j| j.harmonic_order), 1),
            ord.score
        );
    }
}

/// The lines under the firing-order table that say what its columns hold.
fn legend(two_banks: bool, journals: bool) -> String {
    let mut o = String::new();
    if two_banks {
        o.push_str(
            "bank intervals: crank degrees between consecutive firings on each bank, the banks \
             split by |; scheme: how the banks' firings interleave\n",
        );
    } else {
        o.push_str("intervals: crank degrees between consecutive firings\n");
    }
    o.push_str("neighbours: consecutive firings of adjacent cylinders on one bank\n");
    if journals {
        o.push_str(
            "journal N m: the largest torque on any main journal; after throw K: the journal \
             that carries it, the one after throw K counted from the free end\n\
             harmonic N m / order: the largest harmonic amplitude of any journal's torque, and \
             its engine order (per revolution)\n",
        );
    } else {
        o.push_str(
            "journal N m, after throw, harmonic N m / order: the main-journal torques, from a \
             pressure diagram (none given: null)\n",
        );
    }
    o
}

/// `firing_orders.csv`: one row per crank and order, best first.
pub fn firing_csv(s: &Study) -> String {
    let mut o = String::from(
        "crank_rank,crank_angles_deg,mirror_symmetric,engine_crank,order_rank,firing_order,\
         firing_angles_deg,intervals_deg,bank_intervals_deg,scheme,neighbour_consecutive,\
         neighbour_pairs,max_journal_torque_nm,journal_most_loaded,max_journal_harmonic_nm,\
         journal_harmonic_order,free_force_1_n,free_force_2_n,free_moment_1_nm,\
         free_moment_2_nm,free_moment_1_residual_nm,score\n",
    );
    let cell = |v: Option<f64>| v.map_or(String::new(), |x| x.to_string());
    for (ck, c) in s.cranks.iter().enumerate() {
        for (ok, ord) in c.orders.iter().enumerate() {
            let cr = &ord.criteria;
            let j = ord.journal.as_ref();
            let f = &c.free;
            let pairs: Vec<String> = cr
                .neighbour_pairs
                .iter()
                .map(|(a, b)| format!("{a}-{b}"))
                .collect();
            // Text cells never start a formula (`format::csv_text`).
            let text = |s: String| enginedyn_numerics::format::csv_text(&s).into_owned();
            let row = [
                (ck + 1).to_string(),
                text(dashed(&c.crank_angles_deg)),
                c.mirror_symmetric.to_string(),
                c.engine_crank.to_string(),
                (ok + 1).to_string(),
                text(dashed(&ord.order.order)),
                text(dashed(&ord.order.angles_deg)),
                text(dashed(&cr.intervals_deg)),
                text(banks(&cr.bank_intervals_deg)),
                text(cr.scheme.map_or(String::new(), |s| s.name().to_string())),
                cr.neighbour_consecutive.to_string(),
                text(pairs.join(" ")),
                cell(j.map(|j| j.max_torque_nm)),
                j.map_or(String::new(), |j| j.max_torque_journal.to_string()),
                cell(j.map(|j| j.max_harmonic_nm)),
                cell(j.map(|j| j.harmonic_order)),
                f.free_force_1_n.to_string(),
                f.free_force_2_n.to_string(),
                f.free_moment_1_nm.to_string(),
                f.free_moment_2_nm.to_string(),
                f.free_moment_1_residual_nm.to_string(),
                ord.score.to_string(),
            ];
            o.push_str(&row.join(","));
            o.push('\n');
        }
    }
    o
}

/// `1st`, `2nd`, `3rd`, `4th`, … `11th`, `12th`, `21st`.
fn ordinal(n: usize) -> String {
    let suffix = match (n % 10, n % 100) {
        (_, 11..=13) => "th",
        (1, _) => "st",
        (2, _) => "nd",
        (3, _) => "rd",
        _ => "th",
    };
    format!("{n}{suffix}")
}

/// The best crank seen from the free end (it turns clockwise), throw 1 on
/// bank 1's axis at TDC; each throw at its lag counter-clockwise behind it,
/// named with its cylinders and their places in the best firing order
/// ("cyl 3 fires 2nd"). With split pins each cylinder's pin is drawn at its
/// own lag.
pub fn crank_end_view(engine: &Engine, s: &Study) -> Figure {
    let deg = std::f64::consts::PI / 180.0;
    let gamma = match engine.layout() {
        Layout::Inline => 0.0,
        Layout::Vee { bank_angle } => bank_angle.to_degrees(),
        Layout::Boxer => 180.0,
    };
    let axis1 = 90.0 + gamma / 2.0;
    let mut series = vec![Series {
        name: "crank circle".into(),
        points: (0..=72)
            .map(|k| ((k as f64 * 5.0 * deg).cos(), (k as f64 * 5.0 * deg).sin()))
            .collect(),
        dashed: true,
        marker: false,
        color: None,
    }];
    let bank_axes: Vec<f64> = if gamma > 0.0 {
        vec![axis1, axis1 - gamma]
    } else {
        vec![axis1]
    };
    for (b, a) in bank_axes.iter().enumerate() {
        series.push(Series {
            name: format!("bank {} axis", b + 1),
            points: vec![(0.0, 0.0), (1.3 * (a * deg).cos(), 1.3 * (a * deg).sin())],
            dashed: true,
            marker: false,
            color: None,
        });
    }
    let title;
    if let Some(c) = s.cranks.first() {
        let best = c.orders.first();
        title = match best {
            Some(b) => format!(
                "crank end view from the free end (turns clockwise); best order {}",
                dashed(&b.order.order)
            ),
            None => "crank end view from the free end (turns clockwise); no even order".into(),
        };
        let fires = |i: usize| match best {
            Some(b) => {
                let place = b.order.order.iter().position(|&x| x == i + 1).unwrap_or(0);
                format!("cyl {} fires {}", i + 1, ordinal(place + 1))
            }
            None => format!("cyl {}", i + 1),
        };
        let split = c.crank_angles_deg.len() != engine.throws();
        let mut pin = |name: String, alpha: f64| {
            let a = (axis1 + alpha) * deg;
            series.push(Series {
                name,
                points: vec![(0.0, 0.0), (a.cos(), a.sin())],
                dashed: false,
                marker: false,
                color: None,
            });
        };
        for k in 0..engine.throws() {
            let cyls: Vec<usize> = (0..engine.cylinders())
                .filter(|&i| engine.throw_of(i) == k)
                .collect();
            if split {
                for &i in &cyls {
                    let alpha = c.crank_angles_deg[i];
                    pin(
                        format!("throw {}, pin at {}°: {}", k + 1, alpha, fires(i)),
                        alpha,
                    );
                }
            } else {
                let alpha = c.crank_angles_deg[k];
                let named: Vec<String> = cyls.iter().map(|&i| fires(i)).collect();
                pin(
                    format!("throw {} at {}°: {}", k + 1, alpha, named.join(", ")),
                    alpha,
                );
            }
        }
    } else {
        title = "crank end view: no crank".into();
    }
    Figure::single(
        "crank_end_view.svg",
        Chart {
            title,
            x_label: "crank radii".into(),
            y_label: "crank radii".into(),
            series,
            log: false,
            equal: true,
            angle_ticks: None,
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ordinals() {
        let got: Vec<String> = [1, 2, 3, 4, 11, 12, 13, 21, 22, 23, 24]
            .into_iter()
            .map(ordinal)
            .collect();
        assert_eq!(
            got,
            [
                "1st", "2nd", "3rd", "4th", "11th", "12th", "13th", "21st", "22nd", "23rd", "24th"
            ]
        );
    }
}

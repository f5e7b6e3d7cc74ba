//! Charts on logarithmic axes (both x and y), for quantities spanning decades: a study's wall time against its
//! error. Same conventions as [`super::draw_panels`] (atomic write, embedded font, panels stacked, legend where it
//! hides the fewest data), with two differences: every point gets a marker (a point is a run, not a sample of a
//! curve), and a value ≤ 0 has no place on a log axis, so it is skipped and counted like a non-finite one.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::{
    Chart, Drawn, FAMILY, Metrics, PALETTE, PlotError, Prepared, Series, check_panels, draw_atomic, legend_place, pad,
};

/// Draws `charts` stacked top to bottom on log–log axes in one PNG of `size` pixels at `path`, atomically. Returns
/// the path and the number of points skipped (non-finite or ≤ 0).
pub fn draw_log_log(path: &Path, charts: &[Chart], size: (u32, u32)) -> Result<Drawn, PlotError> {
    check_panels(path, charts, size)?;
    // The charts in log10 space: ranges, skipping, segments and the legend's place all work there unchanged.
    let log = |v: &[f64]| -> Vec<f64> { v.iter().map(|&x| if x > 0.0 { x.log10() } else { f64::NAN }).collect() };
    let logs: Vec<Vec<(Vec<f64>, Vec<f64>)>> =
        charts.iter().map(|c| c.series.iter().map(|s| (log(s.x), log(s.y))).collect()).collect();
    let log_charts: Vec<Chart> = charts
        .iter()
        .zip(&logs)
        .map(|(c, l)| Chart {
            title: c.title,
            x_label: c.x_label,
            y_label: c.y_label,
            series: c.series.iter().zip(l).map(|(s, (x, y))| Series { label: s.label, x, y }).collect(),
        })
        .collect();
    let mut prepared = log_charts.iter().map(|c| Prepared::new(path, c)).collect::<Result<Vec<_>, _>>()?;
    for p in &mut prepared {
        // Room for the markers at the ends of the x axis too.
        p.x_range = pad(p.x_range, 0.05);
    }
    let skipped = prepared.iter().map(|p| p.skipped).sum();
    draw_atomic(path, skipped, |target| render(target, &prepared, size))
}

/// Tick positions of a log axis over [lo, hi] (both > 0): powers of ten when the range spans three or more of them
/// (every n-th decade past a dozen), else 1-2-5 or 1…9 per decade, else, for a range within a factor of about
/// two, evenly spaced round values (plotters' own log ticks leave such an axis unlabelled).
fn log_ticks(lo: f64, hi: f64) -> Vec<f64> {
    let (k0, k1) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
    let within = |v: &f64| *v >= lo * (1.0 - 1e-12) && *v <= hi * (1.0 + 1e-12);
    for mantissas in [&[1.0][..], &[1.0, 2.0, 5.0], &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0]] {
        let ticks: Vec<f64> =
            (k0..=k1).flat_map(|k| mantissas.iter().map(move |m| m * 10f64.powi(k))).filter(within).collect();
        if ticks.len() > 12 {
            let every = ticks.len().div_ceil(12);
            return ticks.into_iter().step_by(every).collect();
        }
        if ticks.len() >= 3 {
            return ticks;
        }
    }
    let raw = (hi - lo) / 5.0;
    let e = 10f64.powi(raw.log10().floor() as i32);
    let step = [1.0, 2.0, 5.0, 10.0].iter().map(|m| m * e).find(|s| *s >= raw).unwrap_or(10.0 * e);
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    (first..=last).map(|k| k as f64 * step).filter(|v| *v > 0.0).collect()
}

/// Labels for `ticks`: the fewest significant digits (up to 6) that tell them apart, plain in [10⁻³, 10⁵), else
/// exponent form (`2e-5`).
fn tick_labels(ticks: &[f64]) -> impl Fn(&f64) -> String + use<> {
    let label = |v: f64, digits: usize| -> String {
        if !(v > 0.0 && v.is_finite()) {
            return format!("{v}");
        }
        let mag = v.log10().floor() as i32;
        let s = if (-3..5).contains(&mag) {
            let decimals = (digits as i32 - 1 - mag).max(0) as usize;
            format!("{v:.decimals$}")
        } else {
            format!("{v:.*e}", digits - 1)
        };
        match s.split_once('e') {
            Some((m, e)) if m.contains('.') => format!("{}e{e}", m.trim_end_matches('0').trim_end_matches('.')),
            Some(_) => s,
            None if s.contains('.') => s.trim_end_matches('0').trim_end_matches('.').to_string(),
            None => s,
        }
    };
    let digits = (1..=6)
        .find(|&d| {
            let l: Vec<String> = ticks.iter().map(|&v| label(v, d)).collect();
            l.iter().enumerate().all(|(i, a)| !l[..i].contains(a))
        })
        .unwrap_or(6);
    move |v: &f64| label(*v, digits)
}

fn render(target: &Path, charts: &[Prepared], size: (u32, u32)) -> Result<(), String> {
    let root = BitMapBackend::new(target, size).into_drawing_area();
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let areas = root.split_evenly((charts.len(), 1));
    let panel_height = size.1 / charts.len().max(1) as u32;
    let m = Metrics::new((size.0, size.1.min(panel_height * 3 / 2)));
    let y_label_area = m.text_width("0.0001") + m.font * 2;
    for (area, chart) in areas.iter().zip(charts) {
        render_chart(area, chart, &m, y_label_area)?;
    }
    root.present().map_err(|e| e.to_string())
}

fn render_chart(
    area: &DrawingArea<BitMapBackend, Shift>,
    p: &Prepared,
    m: &Metrics,
    y_label_area: u32,
) -> Result<(), String> {
    let err = |e: &dyn std::fmt::Display| e.to_string();
    let (x0, x1) = (10f64.powf(p.x_range.0), 10f64.powf(p.x_range.1));
    let (y0, y1) = (10f64.powf(p.y_range.0), 10f64.powf(p.y_range.1));
    let (xt, yt) = (log_ticks(x0, x1), log_ticks(y0, y1));
    let (x_fmt, y_fmt) = (tick_labels(&xt), tick_labels(&yt));
    let font = (FAMILY, m.font);
    let mut cc = ChartBuilder::on(area)
        .caption(p.chart.title, (FAMILY, m.title))
        .margin(m.margin)
        .margin_right(m.margin + m.text_width("0.0e-00") / 2)
        .x_label_area_size(m.font * 3)
        .y_label_area_size(y_label_area)
        .build_cartesian_2d((x0..x1).log_scale().with_key_points(xt), (y0..y1).log_scale().with_key_points(yt))
        .map_err(|e| err(&e))?;
    cc.configure_mesh()
        .x_desc(p.chart.x_label)
        .y_desc(p.chart.y_label)
        .x_label_formatter(&x_fmt)
        .y_label_formatter(&y_fmt)
        .label_style(font)
        .axis_desc_style(font)
        .bold_line_style(RGBColor(225, 225, 225))
        .light_line_style(RGBColor(245, 245, 245))
        .draw()
        .map_err(|e| err(&e))?;
    let dot = m.stroke + 3;
    for (i, (series, runs)) in p.chart.series.iter().zip(&p.segments).enumerate() {
        let style = PALETTE[i % PALETTE.len()].stroke_width(m.stroke);
        let label =
            if runs.is_empty() { format!("{} (no drawable values)", series.label) } else { series.label.into() };
        let linear: Vec<Vec<(f64, f64)>> =
            runs.iter().map(|r| r.iter().map(|&(x, y)| (10f64.powf(x), 10f64.powf(y))).collect()).collect();
        let lines = linear.iter().filter(|r| r.len() > 1).map(|r| PathElement::new(r.clone(), style));
        cc.draw_series(lines).map_err(|e| err(&e))?;
        let dots = linear.iter().flatten().map(|&q| Circle::new(q, dot, style.filled()));
        cc.draw_series(dots)
            .map_err(|e| err(&e))?
            .label(label)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], style));
    }
    let label_width = p.chart.series.iter().map(|s| m.text_width(s.label)).max().unwrap_or(0);
    let legend = (label_width + 24 + 4 * m.font, (m.font * 3 / 2) * p.chart.series.len() as u32 + m.font);
    let position = legend_place(p, legend, cc.plotting_area().dim_in_pixel());
    cc.configure_series_labels()
        .position(position)
        .label_font(font)
        .background_style(WHITE.mix(0.85))
        .border_style(RGBColor(160, 160, 160))
        .margin(m.font / 2)
        .draw()
        .map_err(|e| err(&e))?;
    Ok(())
}

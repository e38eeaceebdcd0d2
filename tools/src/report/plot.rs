//! Error-against-cost plots (plotters, SVG backend: no fonts needed at build or run
//! time; the viewer renders the text).

use super::methods::Family;
use plotters::prelude::*;
use std::path::Path;

/// One point of a plot: a method setting.
#[derive(Clone, Debug)]
pub struct Point {
    /// Family (colour).
    pub family: Family,
    /// Setting name (written next to the Pareto-front points).
    pub label: String,
    /// Cost: nanoseconds per ray.
    pub ns: f64,
    /// Cost: texture fetches per ray (mean).
    pub fetches: f64,
    /// Wrong-ray rate in percent of the non-ambiguous rays.
    pub wrong_pct: f64,
}

/// Indices of the points on the Pareto front of `(cost, error)`: no other point is at
/// most as costly and at most as wrong with one of the two strictly smaller.
pub fn pareto(points: &[(f64, f64)]) -> Vec<usize> {
    let mut front: Vec<usize> = (0..points.len())
        .filter(|&i| {
            let (c, e) = points[i];
            !points
                .iter()
                .any(|&(c2, e2)| c2 <= c && e2 <= e && (c2 < c || e2 < e))
        })
        .collect();
    front.sort_by(|&a, &b| points[a].0.total_cmp(&points[b].0));
    front
}

fn rgb(f: Family) -> RGBColor {
    let (r, g, b) = f.colour();
    RGBColor(r, g, b)
}

/// Draws one panel: wrong rate (log, zero drawn on the floor line) against `cost`.
fn panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
    x_desc: &str,
    points: &[Point],
    cost: impl Fn(&Point) -> f64,
    floor: f64,
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    let err = |e: &dyn std::fmt::Display| e.to_string();
    let xs: Vec<f64> = points.iter().map(&cost).map(|c| c.max(1e-3)).collect();
    let ys: Vec<f64> = points.iter().map(|p| p.wrong_pct.max(floor)).collect();
    let (xmin, xmax) = xs
        .iter()
        .fold((f64::INFINITY, 0f64), |(a, b), &x| (a.min(x), b.max(x)));
    let ymax = ys.iter().fold(floor * 10.0, |m, &y| m.max(y)).min(100.0) * 1.5;
    let mut chart = ChartBuilder::on(area)
        .caption(title, ("sans-serif", 16))
        .margin(12)
        .x_label_area_size(36)
        .y_label_area_size(56)
        .build_cartesian_2d(
            (xmin / 1.4..xmax * 1.4).log_scale(),
            (floor / 1.5..ymax).log_scale(),
        )
        .map_err(|e| err(&e))?;
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc("wrong rays, % (0 on the bottom line)")
        .label_style(("sans-serif", 11))
        .x_labels(5)
        .y_labels(8)
        .x_label_formatter(&|v| format!("{v}"))
        .y_label_formatter(&|v| format!("{v}"))
        .axis_desc_style(("sans-serif", 12))
        .light_line_style(RGBColor(235, 235, 235))
        .draw()
        .map_err(|e| err(&e))?;
    // The zero line.
    chart
        .draw_series(LineSeries::new(
            [(xmin / 1.4, floor), (xmax * 1.4, floor)],
            RGBColor(160, 160, 160).stroke_width(1),
        ))
        .map_err(|e| err(&e))?;
    let mut families: Vec<Family> = points.iter().map(|p| p.family).collect();
    families.sort();
    families.dedup();
    for fam in families {
        let colour = rgb(fam);
        let pts: Vec<(f64, f64)> = (0..points.len())
            .filter(|&i| points[i].family == fam)
            .map(|i| (xs[i], ys[i]))
            .collect();
        chart
            .draw_series(pts.iter().map(|&p| Circle::new(p, 4, colour.filled())))
            .map_err(|e| err(&e))?;
    }
    // Pareto front: a staircase through the non-dominated settings, ringed and named.
    let pairs: Vec<(f64, f64)> = xs.iter().copied().zip(ys.iter().copied()).collect();
    let front = pareto(&pairs);
    let mut stairs = Vec::new();
    for (k, &i) in front.iter().enumerate() {
        if k > 0 {
            stairs.push((xs[i], ys[front[k - 1]]));
        }
        stairs.push((xs[i], ys[i]));
    }
    chart
        .draw_series(LineSeries::new(stairs, BLACK.stroke_width(1)))
        .map_err(|e| err(&e))?;
    chart
        .draw_series(front.iter().map(|&i| {
            EmptyElement::at((xs[i], ys[i]))
                + Circle::new((0, 0), 7, BLACK.stroke_width(1))
                + Text::new(points[i].label.clone(), (8, -12), ("sans-serif", 10))
        }))
        .map_err(|e| err(&e))?;
    Ok(())
}

/// Writes the two panels (error against ns/ray and against fetches/ray) of one scene
/// as an SVG. `rays` sets the floor of the log axis (half a ray).
pub fn write_plot(path: &Path, title: &str, points: &[Point], rays: u64) -> Result<(), String> {
    let root = SVGBackend::new(path, (1100, 460)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let (panels, legend) = root.split_vertically(430);
    let (a, b) = panels.split_horizontally(550);
    let floor = 50.0 / rays.max(1) as f64;
    panel(
        &a,
        &format!("{title}: error vs time"),
        "ns per ray (1 thread, median)",
        points,
        |p| p.ns,
        floor,
    )?;
    panel(
        &b,
        &format!("{title}: error vs fetches"),
        "texture fetches per ray (mean)",
        points,
        |p| p.fetches,
        floor,
    )?;
    // The legend, one row under both panels: the families present, then the front.
    let mut families: Vec<Family> = points.iter().map(|p| p.family).collect();
    families.sort();
    families.dedup();
    let style = ("sans-serif", 12).into_font();
    let mut x = 70;
    for fam in families {
        let colour = rgb(fam);
        legend
            .draw(&Circle::new((x, 14), 4, colour.filled()))
            .map_err(|e| e.to_string())?;
        legend
            .draw(&Text::new(fam.name(), (x + 8, 7), style.clone()))
            .map_err(|e| e.to_string())?;
        x += 20 + 6 * fam.name().len() as i32;
    }
    legend
        .draw(&PathElement::new(
            [(x, 14), (x + 14, 14)],
            BLACK.stroke_width(1),
        ))
        .map_err(|e| e.to_string())?;
    legend
        .draw(&Circle::new((x + 7, 14), 6, BLACK.stroke_width(1)))
        .map_err(|e| e.to_string())?;
    legend
        .draw(&Text::new("Pareto front", (x + 18, 7), style))
        .map_err(|e| e.to_string())?;
    root.present().map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::pareto;

    #[test]
    fn pareto_front() {
        // (cost, error): 0 and 2 are on the front; 1 is dominated by 0; 3 ties 2 on
        // error but costs more.
        let pts = [(1.0, 5.0), (2.0, 6.0), (3.0, 0.0), (4.0, 0.0), (0.5, 9.0)];
        assert_eq!(pareto(&pts), vec![4, 0, 2]);
        assert_eq!(pareto(&[]), Vec::<usize>::new());
    }
}

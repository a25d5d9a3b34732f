//! A small SVG writer for print: sizes in points (1 pt = 1/72 in, the SVG's user unit),
//! coordinates written with two decimals (a hundredth of a point, so curves stay smooth
//! at any print resolution), text left to the viewer's fonts.

use std::fmt::Write as _;

/// Fonts, in order of preference; every viewer has one of them.
const FONT_FAMILY: &str = "DejaVu Sans, Helvetica, Arial, sans-serif";

/// A number as SVG wants it: at most two decimals, no trailing zeros, no `-0`.
pub(crate) fn num(v: f64) -> String {
    let r = (v * 100.0).round() / 100.0;
    let r = if r == 0.0 { 0.0 } else { r };
    let s = format!("{r:.2}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    s.to_owned()
}

/// Text escaped for XML content and attributes.
pub(crate) fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c if (c as u32) < 0x20 && c != '\t' => out.push(' '),
            c => out.push(c),
        }
    }
    out
}

/// Mathematical text: `a_b` writes b as a subscript (letters and digits after `_`),
/// everything else is escaped as is. Only for the figures' own labels, never for user text
/// (a law named `paper_bidirectional` stays as written).
pub(crate) fn math(s: &str) -> String {
    let mut out = String::new();
    let mut chars = s.chars().peekable();
    // Text after a subscript goes back up to the baseline in one tspan.
    let mut after: Option<String> = None;
    while let Some(c) = chars.next() {
        if c == '_' && chars.peek().is_some_and(|n| n.is_alphanumeric()) {
            if let Some(rest) = after.take() {
                let _ = write!(out, "<tspan dy=\"-0.3em\">{}</tspan>", escape(&rest));
            }
            let mut sub = String::new();
            while let Some(&n) = chars.peek() {
                if n.is_alphanumeric() {
                    sub.push(n);
                    chars.next();
                } else {
                    break;
                }
            }
            let _ = write!(out, "<tspan dy=\"0.3em\" font-size=\"75%\">{}</tspan>", escape(&sub));
            after = Some(String::new());
        } else if let Some(rest) = after.as_mut() {
            rest.push(c);
        } else {
            out.push_str(&escape(&c.to_string()));
        }
    }
    if let Some(rest) = after.filter(|r| !r.is_empty()) {
        let _ = write!(out, "<tspan dy=\"-0.3em\">{}</tspan>", escape(&rest));
    }
    out
}

/// Horizontal alignment of a text.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Anchor {
    Start,
    Middle,
    End,
}

impl Anchor {
    fn name(self) -> &'static str {
        match self {
            Anchor::Start => "start",
            Anchor::Middle => "middle",
            Anchor::End => "end",
        }
    }
}

/// How a line is drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Stroke<'a> {
    /// Colour, `#rrggbb`.
    pub color: &'a str,
    /// Width, pt.
    pub width: f64,
    /// Dash pattern (`"3 2"`, pt), if any.
    pub dash: Option<&'a str>,
    /// Opacity, 0..1.
    pub opacity: f64,
}

impl<'a> Stroke<'a> {
    /// A solid, opaque line.
    pub fn solid(color: &'a str, width: f64) -> Self {
        Self { color, width, dash: None, opacity: 1.0 }
    }

    fn attrs(&self) -> String {
        let mut a = format!("stroke=\"{}\" stroke-width=\"{}\"", self.color, num(self.width));
        if let Some(d) = self.dash {
            let _ = write!(a, " stroke-dasharray=\"{d}\"");
        }
        if self.opacity < 1.0 {
            let _ = write!(a, " stroke-opacity=\"{}\"", num(self.opacity));
        }
        a
    }
}

/// One SVG document being written.
pub(crate) struct Svg {
    width: f64,
    height: f64,
    defs: String,
    body: String,
    clips: usize,
}

impl Svg {
    /// A white page of `width` x `height` pt.
    pub fn new(width: f64, height: f64) -> Self {
        Self { width, height, defs: String::new(), body: String::new(), clips: 0 }
    }

    /// The document: physical size in mm (so it prints at its intended size), a viewBox in pt.
    pub fn finish(self) -> String {
        let mm = 25.4 / 72.0;
        format!(
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w_mm}mm\" height=\"{h_mm}mm\" viewBox=\"0 0 {w} {h}\" \
             font-family=\"{FONT_FAMILY}\" stroke-linejoin=\"round\" stroke-linecap=\"round\">\n\
             <defs>{defs}</defs>\n<rect width=\"{w}\" height=\"{h}\" fill=\"#ffffff\"/>\n{body}</svg>\n",
            w_mm = num(self.width * mm),
            h_mm = num(self.height * mm),
            w = num(self.width),
            h = num(self.height),
            defs = self.defs,
            body = self.body,
        )
    }

    /// A clip path for the rectangle at (x, y) of size w x h (pt); returns its id.
    pub fn clip_rect(&mut self, x: f64, y: f64, w: f64, h: f64) -> String {
        self.clips += 1;
        let id = format!("clip{}", self.clips);
        let _ = write!(
            self.defs,
            "<clipPath id=\"{id}\"><rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\"/></clipPath>",
            num(x),
            num(y),
            num(w),
            num(h)
        );
        id
    }

    /// Starts a group clipped to `clip` (an id from [`Svg::clip_rect`]).
    pub fn begin_clip(&mut self, clip: &str) {
        let _ = writeln!(self.body, "<g clip-path=\"url(#{clip})\">");
    }

    /// Ends the group of [`Svg::begin_clip`].
    pub fn end_clip(&mut self) {
        self.body.push_str("</g>\n");
    }

    /// A straight line (pt).
    pub fn line(&mut self, a: (f64, f64), b: (f64, f64), s: Stroke<'_>) {
        let _ = writeln!(
            self.body,
            "<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" {}/>",
            num(a.0),
            num(a.1),
            num(b.0),
            num(b.1),
            s.attrs()
        );
    }

    /// An open polyline through `points` (pt); consecutive duplicates (after rounding to
    /// the written precision) are dropped, so long runs at rest cost nothing.
    pub fn polyline(&mut self, points: &[(f64, f64)], s: Stroke<'_>) {
        if points.len() < 2 {
            return;
        }
        let mut pts = String::with_capacity(points.len() * 14);
        let mut last = String::new();
        for &(x, y) in points {
            let p = format!("{},{}", num(x), num(y));
            if p != last {
                if !pts.is_empty() {
                    pts.push(' ');
                }
                pts.push_str(&p);
                last = p;
            }
        }
        let _ = writeln!(self.body, "<polyline points=\"{pts}\" fill=\"none\" {}/>", s.attrs());
    }

    /// A closed polygon (pt), filled and optionally outlined.
    pub fn polygon(&mut self, points: &[(f64, f64)], fill: &str, outline: Option<Stroke<'_>>) {
        let pts: Vec<String> = points.iter().map(|&(x, y)| format!("{},{}", num(x), num(y))).collect();
        let stroke = outline.map_or_else(|| "stroke=\"none\"".to_owned(), |s| s.attrs());
        let _ = writeln!(self.body, "<polygon points=\"{}\" fill=\"{fill}\" {stroke}/>", pts.join(" "));
    }

    /// A circle at (cx, cy) of radius r (pt).
    pub fn circle(&mut self, c: (f64, f64), r: f64, fill: &str, outline: Option<Stroke<'_>>) {
        let stroke = outline.map_or_else(|| "stroke=\"none\"".to_owned(), |s| s.attrs());
        let _ = writeln!(
            self.body,
            "<circle cx=\"{}\" cy=\"{}\" r=\"{}\" fill=\"{fill}\" {stroke}/>",
            num(c.0),
            num(c.1),
            num(r)
        );
    }

    /// A rectangle (pt).
    pub fn rect(&mut self, x: f64, y: f64, w: f64, h: f64, fill: &str, outline: Option<Stroke<'_>>) {
        let stroke = outline.map_or_else(|| "stroke=\"none\"".to_owned(), |s| s.attrs());
        let _ = writeln!(
            self.body,
            "<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"{fill}\" {stroke}/>",
            num(x),
            num(y),
            num(w),
            num(h)
        );
    }

    /// A rectangle (pt) of class `class` (so a reader can find it), its fill of opacity
    /// `fill_opacity` (0..1).
    #[allow(clippy::too_many_arguments)]
    pub fn rect_class(
        &mut self,
        class: &str,
        x: f64,
        y: f64,
        w: f64,
        h: f64,
        fill: &str,
        fill_opacity: f64,
        outline: Option<Stroke<'_>>,
    ) {
        let stroke = outline.map_or_else(|| "stroke=\"none\"".to_owned(), |s| s.attrs());
        let _ = writeln!(
            self.body,
            "<rect class=\"{}\" x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"{fill}\" fill-opacity=\"{}\" {stroke}/>",
            escape(class),
            num(x),
            num(y),
            num(w),
            num(h),
            num(fill_opacity)
        );
    }

    /// Text at (x, y) (pt, the baseline), `markup` already escaped (see [`escape`], [`math`]),
    /// `size` in pt, turned by `rotate` degrees about its anchor.
    pub fn text(&mut self, at: (f64, f64), markup: &str, size: f64, anchor: Anchor, rotate: f64, bold: bool) {
        let mut attrs = format!(
            "x=\"{}\" y=\"{}\" font-size=\"{}\" text-anchor=\"{}\" fill=\"#000000\" xml:space=\"preserve\"",
            num(at.0),
            num(at.1),
            num(size),
            anchor.name()
        );
        if bold {
            attrs.push_str(" font-weight=\"bold\"");
        }
        if rotate != 0.0 {
            let _ = write!(attrs, " transform=\"rotate({} {} {})\"", num(rotate), num(at.0), num(at.1));
        }
        let _ = writeln!(self.body, "<text {attrs}>{markup}</text>");
    }

    /// An arrow from `a` to `b` (pt) with a filled head of length `head` (pt).
    pub fn arrow(&mut self, a: (f64, f64), b: (f64, f64), head: f64, s: Stroke<'_>) {
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let len = dx.hypot(dy);
        if len < 1e-9 {
            return;
        }
        let (ux, uy) = (dx / len, dy / len);
        let head = head.min(0.8 * len);
        let base = (b.0 - ux * head, b.1 - uy * head);
        self.line(a, base, s);
        let half = 0.45 * head;
        let left = (base.0 - uy * half, base.1 + ux * half);
        let right = (base.0 + uy * half, base.1 - ux * half);
        self.polygon(&[b, left, right], s.color, None);
    }
}

/// Width (pt) a text takes at `size` pt, from DejaVu Sans's advance widths (in em; the
/// widest of the three fonts asked for, so Helvetica and Arial fit in it too): narrow
/// letters, spaces and punctuation count for what they take, not an average letter's
/// width; used only to make room for legends and tick labels.
pub(crate) fn text_width(s: &str, size: f64) -> f64 {
    let em: f64 = s
        .chars()
        .map(|c| match c {
            'i' | 'j' | 'l' | '\'' | '|' => 0.28,
            ' ' | ',' | '.' | ':' | ';' | '!' => 0.33,
            'f' | 't' | 'r' | '(' | ')' | '[' | ']' | '-' | '/' | 'I' | 'J' => 0.41,
            'm' | 'w' | 'M' | 'W' | '%' | '\u{2212}' | '=' | '+' | '<' | '>' | '\u{2265}' | '\u{2264}' => 0.98,
            'A'..='Z' => 0.78,
            '0'..='9' => 0.64,
            _ => 0.64,
        })
        .sum();
    em * size
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_keep_two_decimals_and_no_negative_zero() {
        assert_eq!(num(1.0), "1");
        assert_eq!(num(1.23456), "1.23");
        assert_eq!(num(-0.001), "0");
        assert_eq!(num(-12.5), "-12.5");
    }

    #[test]
    fn math_subscripts_only_after_underscores() {
        assert_eq!(math("a<b"), "a&lt;b");
        assert!(math("θ_d − θ").contains("<tspan dy=\"0.3em\" font-size=\"75%\">d</tspan>"));
        assert!(math("θ_d − θ").ends_with("<tspan dy=\"-0.3em\"> − θ</tspan>"), "{}", math("θ_d − θ"));
    }
}

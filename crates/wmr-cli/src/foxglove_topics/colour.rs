//! Run colours, one per run, shared by the layout's plots and the 3D panel's paths so a
//! run looks the same everywhere.

use foxglove::messages::Color;

/// Run colours, `#rrggbb`: Tableau 10 for runs 0-9, then hues a golden angle apart.
/// The layout's plot series and the 3D panel's paths use the same colour per run.
pub fn run_rgb(run: usize) -> [u8; 3] {
    const TABLEAU: [[u8; 3]; 10] = [
        [0x4e, 0x79, 0xa7],
        [0xf2, 0x8e, 0x2b],
        [0xe1, 0x57, 0x59],
        [0x76, 0xb7, 0xb2],
        [0x59, 0xa1, 0x4f],
        [0xed, 0xc9, 0x48],
        [0xb0, 0x7a, 0xa1],
        [0xff, 0x9d, 0xa7],
        [0x9c, 0x75, 0x5f],
        [0xba, 0xb0, 0xac],
    ];
    if let Some(c) = TABLEAU.get(run) {
        return *c;
    }
    // HSL (hue, 0.65, 0.5) to RGB.
    let h = (run as f64 * 137.507_764_050_037_85).rem_euclid(360.0) / 60.0;
    let (s, l) = (0.65, 0.5);
    let c = (1.0 - (2.0 * l - 1.0_f64).abs()) * s;
    let x = c * (1.0 - (h.rem_euclid(2.0) - 1.0).abs());
    let (r, g, b) = match h as u32 {
        0 => (c, x, 0.0),
        1 => (x, c, 0.0),
        2 => (0.0, c, x),
        3 => (0.0, x, c),
        4 => (x, 0.0, c),
        _ => (c, 0.0, x),
    };
    let m = l - 0.5 * c;
    let byte = |v: f64| ((v + m) * 255.0).round().clamp(0.0, 255.0) as u8;
    [byte(r), byte(g), byte(b)]
}

/// The colour of run `run` as `#rrggbb`.
pub fn run_hex(run: usize) -> String {
    let [r, g, b] = run_rgb(run);
    format!("#{r:02x}{g:02x}{b:02x}")
}

/// The colour of run `run` with opacity `a`.
pub fn run_color(run: usize, a: f64) -> Color {
    let [r, g, b] = run_rgb(run);
    Color { r: f64::from(r) / 255.0, g: f64::from(g) / 255.0, b: f64::from(b) / 255.0, a }
}

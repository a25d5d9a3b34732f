//! Random sweep starts avoid the obstacles (issue 41): a start whose footprint would touch
//! a `[[world.obstacle]]` is drawn again from the same generator, counted, and a sweep
//! whose free area is too small is refused naming `sweep.random`.

use wmr_scenario::Scenario;

const FOOTPRINT: f64 = 0.2;
const POST: (f64, f64, f64) = (1.0, 0.0, 0.5);

fn sweep(radius: f64, post: Option<(f64, f64, f64)>) -> String {
    let obstacle = post.map_or(String::new(), |(x, y, r)| {
        format!("[[world.obstacle]]\nkind = \"circle\"\ncenter = {{ x = {x}, y = {y} }}\nradius = {r}\n")
    });
    format!(
        r#"
[robot]
footprint_radius = {FOOTPRINT}
{obstacle}
[sweep]
goal = {{ x = 0.0, y = 0.0, theta_deg = 0.0 }}
controllers = [{{ kind = "graceful" }}]
random = {{ n = 200, seed = 5, radius = {radius}, min_radius = 0.5 }}
"#
    )
}

/// The draws of `random = { seed, radius, min_radius }` as docs/scenario.md states them
/// (fastrand's generator; r^2 uniform over the annulus, then the angle, then the heading),
/// written here, before any is refused.
fn draws(seed: u64, radius: f64, min_radius: f64) -> impl Iterator<Item = (f64, f64, f64)> {
    let mut rng = fastrand::Rng::with_seed(seed);
    let (a2, b2) = (min_radius * min_radius, radius * radius);
    std::iter::from_fn(move || {
        let rho = (a2 + (b2 - a2) * rng.f64()).sqrt();
        let phi = std::f64::consts::TAU * rng.f64();
        let theta = std::f64::consts::TAU * rng.f64() - std::f64::consts::PI;
        Some((rho * phi.cos(), rho * phi.sin(), theta))
    })
}

/// The footprint's clearance from the post at (x, y): the distance between the circles.
fn clearance(x: f64, y: f64) -> f64 {
    (x - POST.0).hypot(y - POST.1) - POST.2 - FOOTPRINT
}

#[test]
fn random_starts_on_an_obstacle_are_drawn_again_and_counted() {
    let sc = Scenario::from_toml_str(&sweep(2.0, Some(POST)), "free").expect("valid");
    let spec = sc.sweep().expect("a sweep");
    assert_eq!(spec.starts.len(), 200);
    assert!(spec.starts.iter().all(|p| clearance(p.x, p.y) > 0.0));
    // The free draws of the generator, in order; the others counted.
    let mut refused = 0;
    let want: Vec<(f64, f64, f64)> = draws(5, 2.0, 0.5)
        .filter(|&(x, y, _)| {
            let free = clearance(x, y) > 0.0;
            refused += usize::from(!free);
            free
        })
        .take(200)
        .collect();
    let got: Vec<(f64, f64, f64)> = spec.starts.iter().map(|p| (p.x, p.y, p.theta)).collect();
    assert_eq!(got, want);
    assert!(refused > 10, "the post covers part of the annulus: {refused}");
    assert_eq!(spec.redrawn_starts, refused);
    // No run starts in contact: none ends collided at t = 0.
    let outcomes = spec.run(sc.sim(), &|| {}).expect("runs");
    assert!(outcomes.iter().all(|o| o.outcome.t_final > 0.0));
    // Without the obstacle: the first 200 draws, none drawn again (as before).
    let sc = Scenario::from_toml_str(&sweep(2.0, None), "open").expect("valid");
    let spec = sc.sweep().expect("a sweep");
    let first: Vec<(f64, f64, f64)> = draws(5, 2.0, 0.5).take(200).collect();
    assert_eq!(spec.starts.iter().map(|p| (p.x, p.y, p.theta)).collect::<Vec<_>>(), first);
    assert_eq!(spec.redrawn_starts, 0);
}

#[test]
fn an_annulus_under_the_obstacle_is_refused_naming_sweep_random() {
    // The post covers the whole annulus 0.5 .. 0.6 m around the goal.
    let e = Scenario::from_toml_str(&sweep(0.6, Some((0.0, 0.0, 3.0))), "crowded").expect_err("no free start");
    assert_eq!(e.key, "sweep.random", "{e}");
    assert!(e.message.contains("too small"), "{e}");
}

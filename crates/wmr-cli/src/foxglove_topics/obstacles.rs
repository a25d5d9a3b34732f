//! The world's obstacles as the 3D panel draws them (`/runN/obstacles`): one entity
//! `obstacleK` per obstacle (K in [`Obstacles::iter`]'s order, the summary's
//! `collided_with`), circles as grey discs (cylinders of the footprint radius' height),
//! polygons as grey outlines; at a collision the obstacle touched again in red, a little
//! higher so it shows above the other runs' grey copy, and the footprint where it touched.

use foxglove::messages::{
    Color, CylinderPrimitive, LinePrimitive, Point3, Pose, Quaternion, SceneEntity, SceneUpdate, Timestamp, Vector3,
    line_primitive,
};
use wmr_core::obstacle::{Obstacle, Obstacles};

use super::topics::WORLD_FRAME;

/// Line width of a polygon's outline and of the footprint, screen pixels.
const OUTLINE_PX: f64 = 3.0;

/// Vertices of a drawn circle (the footprint).
const CIRCLE_VERTICES: usize = 48;

/// An obstacle's grey.
const GREY: Color = Color { r: 0.35, g: 0.35, b: 0.35, a: 1.0 };

/// A collision's red.
const RED: Color = Color { r: 0.9, g: 0.1, b: 0.1, a: 1.0 };

/// The entity id of obstacle `k`.
pub fn obstacle_id(k: usize) -> String {
    format!("obstacle{k}")
}

/// The entity id of the footprint at a collision.
pub const FOOTPRINT_ENTITY: &str = "footprint";

fn at(x: f64, y: f64, z: f64) -> Pose {
    Pose { position: Some(Vector3 { x, y, z }), orientation: Some(Quaternion { x: 0.0, y: 0.0, z: 0.0, w: 1.0 }) }
}

fn outline(points: Vec<Point3>, color: Color) -> LinePrimitive {
    LinePrimitive {
        r#type: line_primitive::Type::LineLoop as i32,
        pose: Some(at(0.0, 0.0, 0.0)),
        thickness: OUTLINE_PX,
        scale_invariant: true,
        points,
        color: Some(color),
        ..Default::default()
    }
}

/// The entity of obstacle `k` (`ob`), drawn `height` m high (a polygon's outline at that
/// height) in `color`, stamped `ts`.
fn entity(k: usize, ob: &Obstacle<'_, f64>, height: f64, color: Color, ts: Option<Timestamp>) -> SceneEntity {
    let mut e = SceneEntity { timestamp: ts, frame_id: WORLD_FRAME.into(), id: obstacle_id(k), ..Default::default() };
    match *ob {
        Obstacle::Circle { center: (x, y), radius } => e.cylinders.push(CylinderPrimitive {
            pose: Some(at(x, y, 0.5 * height)),
            size: Some(Vector3 { x: 2.0 * radius, y: 2.0 * radius, z: height }),
            bottom_scale: 1.0,
            top_scale: 1.0,
            color: Some(color),
        }),
        Obstacle::Polygon(points) => {
            e.lines.push(outline(points.iter().map(|&(x, y)| Point3 { x, y, z: height }).collect(), color));
        }
    }
    e
}

/// Height of the drawn obstacles, m: the footprint radius (flat seen from above).
fn height(obstacles: &Obstacles<f64>) -> f64 {
    obstacles.footprint_radius()
}

/// The scene of `obstacles` at t = 0 (stamp `ts`): every obstacle, grey.
pub fn scene(obstacles: &Obstacles<f64>, ts: Option<Timestamp>) -> SceneUpdate {
    let h = height(obstacles);
    SceneUpdate {
        deletions: vec![],
        entities: obstacles.iter().enumerate().map(|(k, ob)| entity(k, &ob, h, GREY, ts)).collect(),
    }
}

/// The collision of a run whose C ended at (`x`, `y`) (world frame), stamped `ts`: the
/// obstacle its footprint touches (the nearest, when the clearance is <= 0, the core's
/// rule) in red, and the footprint there; `None` when it touches none.
pub fn collision(obstacles: &Obstacles<f64>, x: f64, y: f64, ts: Option<Timestamp>) -> Option<SceneUpdate> {
    let (k, clearance) = obstacles.nearest(x, y)?;
    if clearance > 0.0 {
        return None;
    }
    let ob = obstacles.iter().nth(k)?;
    let h = 1.5 * height(obstacles);
    let r = obstacles.footprint_radius();
    let ring = (0..CIRCLE_VERTICES)
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / CIRCLE_VERTICES as f64;
            Point3 { x: x + r * a.cos(), y: y + r * a.sin(), z: h }
        })
        .collect();
    let footprint = SceneEntity {
        timestamp: ts,
        frame_id: WORLD_FRAME.into(),
        id: FOOTPRINT_ENTITY.into(),
        lines: vec![outline(ring, RED)],
        ..Default::default()
    };
    Some(SceneUpdate { deletions: vec![], entities: vec![entity(k, &ob, h, RED, ts), footprint] })
}

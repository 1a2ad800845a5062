//! The 3D turtle (seed 004, §10.3; ABOP §1.5): a position and a frame of heading H, left L and up
//! U (H × L = U), turned by the symbols `+ -` (about U), `& ^` (about L), `\ /` (about H) and `|`.

use crate::math::{Quat, Vec3};

/// A turtle's position and orientation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Turtle {
    /// Where the turtle stands.
    pub position: Vec3,
    /// The direction it moves in (unit).
    pub heading: Vec3,
    /// Its left (unit, ⟂ heading).
    pub left: Vec3,
    /// Its up: heading × left.
    pub up: Vec3,
}

impl Default for Turtle {
    /// At the origin heading up +z, left +x, up +y.
    fn default() -> Turtle {
        Turtle { position: Vec3::ZERO, heading: Vec3::Z, left: Vec3::X, up: Vec3::Y }
    }
}

impl Turtle {
    fn turn(&mut self, axis: Vec3, degrees: f64) {
        let q = Quat::from_axis_angle(axis, degrees.to_radians());
        self.heading = (q * self.heading).normalize();
        self.left = (q * self.left).normalize();
        self.up = self.heading.cross(self.left).normalize();
        // Keep the frame orthonormal over long strings.
        self.left = self.up.cross(self.heading).normalize();
    }

    /// `+` (positive `degrees`) and `-`: turn about U; `+` turns the heading towards L.
    pub fn yaw(&mut self, degrees: f64) {
        self.turn(self.up, degrees);
    }

    /// `&` (positive `degrees`, pitch down: the heading turns away from U) and `^`.
    pub fn pitch(&mut self, degrees: f64) {
        self.turn(self.left, degrees);
    }

    /// `\` (positive `degrees`, roll left: L turns towards U) and `/`.
    pub fn roll(&mut self, degrees: f64) {
        self.turn(self.heading, degrees);
    }

    /// Applies the turtle symbol `symbol` with angle `degrees`; false for a symbol that does not
    /// turn.
    pub fn apply(&mut self, symbol: &str, degrees: f64) -> bool {
        match symbol {
            "+" => self.yaw(degrees),
            "-" => self.yaw(-degrees),
            "&" => self.pitch(degrees),
            "^" => self.pitch(-degrees),
            "\\" => self.roll(degrees),
            "/" => self.roll(-degrees),
            "|" => self.yaw(180.0),
            _ => return false,
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn near(a: Vec3, b: Vec3) {
        assert!(a.distance(b) < 1e-12, "{a} vs {b}, off by {}", a.distance(b));
    }

    #[test]
    fn turns_follow_the_right_hand_rule_of_the_frame() {
        let mut t = Turtle::default();
        t.yaw(90.0); // + : heading towards left
        near(t.heading, Vec3::X);
        let mut t = Turtle::default();
        t.pitch(90.0); // & : pitch down, away from up
        near(t.heading, Vec3::NEG_Y);
        let mut t = Turtle::default();
        t.roll(90.0); // \ : left towards up
        near(t.left, Vec3::Y);
        near(t.heading, Vec3::Z);
        let mut t = Turtle::default();
        assert!(t.apply("|", 25.0));
        near(t.heading, Vec3::NEG_Z);
        assert!(!t.apply("F", 25.0));
        near(t.heading.cross(t.left), t.up);
    }
}

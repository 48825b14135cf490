//! The classes of the design points (model.md §6): what a point's R and damping say of it, or
//! that it lies around a jump or has no data. [`super::zones`] gives each point its class and
//! makes the zones from them; a point ([`super::point::PointStats`]) and a zone carry theirs.

/// The class of a design point ([`super::zones`] says when a point has which).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Class {
    StrongReliable,
    WeakReliable,
    StrongNotShown,
    WeakNotShown,
    AroundJump,
    NoData,
    StrongNotComputed,
    WeakNotComputed,
}

impl Class {
    pub const ALL: [Class; 8] = [
        Class::StrongReliable,
        Class::WeakReliable,
        Class::StrongNotShown,
        Class::WeakNotShown,
        Class::AroundJump,
        Class::NoData,
        Class::StrongNotComputed,
        Class::WeakNotComputed,
    ];

    pub fn label(self) -> &'static str {
        match self {
            Class::StrongReliable => "strong damping, reliable",
            Class::WeakReliable => "reliable, weak damping",
            Class::StrongNotShown => "strong damping, reliability not shown",
            Class::WeakNotShown => "weak damping, reliability not shown",
            Class::AroundJump => "around a jump",
            Class::NoData => "no data",
            Class::StrongNotComputed => "strong damping, reliability not computed",
            Class::WeakNotComputed => "weak damping, reliability not computed",
        }
    }

    /// A zone of this class may hold a recommended design: R shown at or above `r_min` and no
    /// jump nearby.
    pub fn recommended(self) -> bool {
        matches!(self, Class::StrongReliable | Class::WeakReliable)
    }

    /// Never merged away nor merged into (see [`super::regions`]).
    pub fn sticky(self) -> bool {
        matches!(self, Class::AroundJump | Class::NoData)
    }

    /// The class `c as u8` gave.
    pub(super) fn from_u8(c: u8) -> Class {
        Class::ALL[c as usize]
    }
}

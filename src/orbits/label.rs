//! The labels of continuation points (docs/model.md, §12): what [`super::continuation`] finds
//! between two points and [`super::locate`] solves for, and what the two-parameter curves
//! ([`super::twopar`]) follow. Below both, so that neither imports the other for it.

/// A label of a continuation point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Label {
    None,
    SN,
    /// A branch point: a real multiplier through `+1` where the branch does not fold.
    BP,
    PD,
    /// Neimark–Sacker: a complex pair of multipliers through the unit circle.
    NS,
    GR,
    NI,
}

impl Label {
    pub fn name(self) -> &'static str {
        match self {
            Label::None => "",
            Label::SN => "SN",
            Label::BP => "BP",
            Label::PD => "PD",
            Label::NS => "NS",
            Label::GR => "GR",
            Label::NI => "NI",
        }
    }

    /// The label of a bifurcation a two-parameter curve can follow, by its name ([`Label::name`]):
    /// `SN`, `PD`, `NS` or `GR`; nothing for any other name.
    pub fn of_name(name: &str) -> Option<Label> {
        match name {
            "SN" => Some(Label::SN),
            "PD" => Some(Label::PD),
            "NS" => Some(Label::NS),
            "GR" => Some(Label::GR),
            _ => None,
        }
    }
}

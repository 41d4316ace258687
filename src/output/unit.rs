//! The unit of a coordinate, guessed from its name, for axis labels and the animation's plots.

/// Physical kind of a coordinate, which sets the units on its axes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Unit {
    /// An angle: rad, rad/s, generalised force in N m.
    Angle,
    /// A length: m, m/s, generalised force in N.
    Length,
    /// Unknown: no units printed.
    Unknown,
}

impl Unit {
    /// Guesses from the coordinate name: `x`, `y`, `z`, `s` alone or followed by `_...` or
    /// digits (`x_c`, `y2`, `s_1`) are lengths; every other name is an angle.
    pub fn guess(name: &str) -> Self {
        let mut chars = name.chars();
        let first = chars.next().map(|c| c.to_ascii_lowercase());
        let rest = chars.as_str();
        let length_like = matches!(first, Some('x' | 'y' | 'z' | 's'))
            && (rest.is_empty()
                || rest.starts_with('_')
                || rest.chars().all(|c| c.is_ascii_digit()));
        if length_like {
            Self::Length
        } else {
            Self::Angle
        }
    }

    /// Unit of the coordinate itself (`rad`, `m`, or empty).
    pub fn position(self) -> &'static str {
        match self {
            Self::Angle => "rad",
            Self::Length => "m",
            Self::Unknown => "",
        }
    }

    /// Unit of its rate (`rad/s`, `m/s`, or empty).
    pub fn rate(self) -> &'static str {
        match self {
            Self::Angle => "rad/s",
            Self::Length => "m/s",
            Self::Unknown => "",
        }
    }

    /// Unit of the generalised force on it (`N m`, `N`, or empty).
    pub fn force(self) -> &'static str {
        match self {
            Self::Angle => "N m",
            Self::Length => "N",
            Self::Unknown => "",
        }
    }
}

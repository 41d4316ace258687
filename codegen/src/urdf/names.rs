//! Names: URDF link and joint names as identifiers of the declaration language, and the
//! robot's name as a struct name.

/// Names a declaration gives a meaning of its own: time, pi, the gravity parameter, the
/// world frame, and the functions (a coordinate called `sin` would read as a call).
pub(crate) const RESERVED: &[&str] = &[
    "t", "pi", "g", "world", "der", "sin", "cos", "tan", "exp", "ln", "sqrt", "atan2", "abs", "pow",
];

/// `name` as an identifier: characters other than ASCII letters, digits and `_` become `_`,
/// and a name that starts with a digit, or has only underscores, gets `prefix` (`j_` for a
/// joint's coordinate, `l_` for a link).
pub(crate) fn identifier(name: &str, prefix: &str) -> String {
    let safe: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    let needs_prefix =
        safe.starts_with(|c: char| c.is_ascii_digit()) || safe.chars().all(|c| c == '_');
    if needs_prefix {
        format!("{prefix}{safe}")
    } else {
        safe
    }
}

/// True when `name` is an ASCII identifier: a letter or `_` first, then letters, digits and
/// `_`, and not `_` alone.
pub(crate) fn is_identifier(name: &str) -> bool {
    let mut chars = name.chars();
    matches!(chars.next(), Some(c) if c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
        && name != "_"
}

/// Rust's keywords (strict and reserved, 2024 edition): no struct may be named one.
const RUST_KEYWORDS: &[&str] = &[
    "as", "async", "await", "break", "const", "continue", "crate", "dyn", "else", "enum", "extern",
    "false", "fn", "for", "gen", "if", "impl", "in", "let", "loop", "match", "mod", "move", "mut",
    "pub", "ref", "return", "self", "Self", "static", "struct", "super", "trait", "true", "type",
    "unsafe", "use", "where", "while", "abstract", "become", "box", "do", "final", "macro",
    "override", "priv", "try", "typeof", "unsized", "virtual", "yield",
];

/// True when `name` is one of Rust's keywords.
pub(crate) fn is_keyword(name: &str) -> bool {
    RUST_KEYWORDS.contains(&name)
}

/// The robot's name in CamelCase as a struct name: `panda` gives `Panda`, `ur5_robot`
/// gives `Ur5Robot`; a name that would start with a digit gets `Robot` in front, a Rust
/// keyword (`self` gives `Self`) too, and an empty one is `Robot`.
pub(crate) fn struct_name(robot: &str) -> String {
    let camel: String = robot
        .split(|c: char| !c.is_ascii_alphanumeric())
        .filter(|w| !w.is_empty())
        .map(|w| {
            let mut chars = w.chars();
            chars
                .next()
                .map(|c| c.to_ascii_uppercase().to_string() + chars.as_str())
                .unwrap_or_default()
        })
        .collect();
    if camel.is_empty() || camel.starts_with(|c: char| c.is_ascii_digit()) || is_keyword(&camel) {
        format!("Robot{camel}")
    } else {
        camel
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identifiers_table() {
        for (name, prefix, expected) in [
            ("panda_joint1", "j_", "panda_joint1"),
            ("arm/elbow-2", "j_", "arm_elbow_2"),
            ("2nd", "j_", "j_2nd"),
            ("-", "l_", "l__"),
            ("é", "l_", "l__"),
        ] {
            assert_eq!(identifier(name, prefix), expected, "{name}");
            assert!(is_identifier(&identifier(name, prefix)), "{name}");
        }
    }

    #[test]
    fn struct_names_table() {
        for (robot, expected) in [
            ("panda", "Panda"),
            ("ur5_robot", "Ur5Robot"),
            ("my-robot arm", "MyRobotArm"),
            ("6dof", "Robot6dof"),
            ("", "Robot"),
            ("KUKA_lbr", "KUKALbr"),
            ("self", "RobotSelf"),
        ] {
            assert_eq!(struct_name(robot), expected, "{robot}");
        }
    }
}

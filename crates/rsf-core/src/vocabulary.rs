//! Closed vocabularies — options, modes, units — as enums parsed once at the edge.
//!
//! [`vocabulary!`](crate::vocabulary!) gives a fieldless enum its names in one place: `ALL`,
//! `name()`, `FromStr` (the error lists the names), `Display` and serde by name. The names are matched
//! exhaustively, so a new variant fails to compile until it has one; the CLI lists `ALL` as
//! clap's possible values, Python, manifests and protocol files parse with the same
//! `FromStr`.
//!
//! ```
//! #[derive(Clone, Copy, Debug, PartialEq, Eq)]
//! enum Unit { Um, Mm }
//! rsf_core::vocabulary!(Unit, "unit", { Um => "um" | "µm", Mm => "mm" });
//! assert_eq!("µm".parse::<Unit>(), Ok(Unit::Um));
//! assert_eq!(Unit::Mm.to_string(), "mm");
//! assert_eq!("cm".parse::<Unit>().unwrap_err(), "unknown unit `cm`: use um or mm");
//! ```

/// `a`, `a or b`, `a, b or c`.
pub fn one_of(names: &[&str]) -> String {
    match names {
        [] => String::new(),
        [one] => (*one).to_string(),
        [rest @ .., last] => format!("{} or {last}", rest.join(", ")),
    }
}

/// Gives a fieldless enum its names: `TYPE, "what it is (for messages)", { Variant => "name" |
/// "alias"…, … }`. See the [module](mod@crate::vocabulary).
#[macro_export]
macro_rules! vocabulary {
    ($ty:ident, $what:literal, { $($variant:ident => $name:literal $(| $alias:literal)*),+ $(,)? }) => {
        impl $ty {
            /// Every value, in the order of its names.
            pub const ALL: &'static [$ty] = &[$($ty::$variant),+];
            /// Every name, in the order of [`Self::ALL`].
            pub const NAMES: &'static [&'static str] = &[$($name),+];
            /// The name (in options, files and JSON).
            pub fn name(self) -> &'static str {
                match self {
                    $($ty::$variant => $name),+
                }
            }
        }
        impl ::std::str::FromStr for $ty {
            type Err = String;
            /// A value by its name (or an alias); the error lists the names.
            fn from_str(s: &str) -> Result<Self, String> {
                match s {
                    $($name $(| $alias)* => Ok($ty::$variant),)+
                    other => Err(format!("unknown {} `{other}`: use {}", $what, $crate::vocabulary::one_of($ty::NAMES))),
                }
            }
        }
        impl ::std::fmt::Display for $ty {
            fn fmt(&self, f: &mut ::std::fmt::Formatter<'_>) -> ::std::fmt::Result {
                f.pad(self.name())
            }
        }
        impl $crate::__serde::Serialize for $ty {
            fn serialize<S: $crate::__serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
                s.serialize_str(self.name())
            }
        }
        impl<'de> $crate::__serde::Deserialize<'de> for $ty {
            fn deserialize<D: $crate::__serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
                let s = <::std::string::String as $crate::__serde::Deserialize>::deserialize(d)?;
                s.parse().map_err(<D::Error as $crate::__serde::de::Error>::custom)
            }
        }
    };
}

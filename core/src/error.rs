//! Parameter validation errors: every constructor that takes user input returns
//! [`ParamError`], which names the field, the offending value and the allowed range.

use std::fmt;

/// A rejected parameter: which field, what value was given, what is allowed.
///
/// Built on any thread (usually the thread parsing a scene or CLI arguments); never on the
/// audio thread's hot path.
#[derive(Debug, Clone, PartialEq)]
pub struct ParamError {
    /// Dotted name of the parameter as the user wrote it (for example `omega0` or `plate.radius`).
    pub field: String,
    /// The value that was given, formatted for display.
    pub value: String,
    /// Human-readable description of the allowed values (for example `(0, inf)`).
    pub allowed: String,
}

impl ParamError {
    /// Builds an error for `field` with the given value and allowed range description.
    pub fn new(
        field: impl Into<String>,
        value: impl fmt::Display,
        allowed: impl Into<String>,
    ) -> Self {
        Self {
            field: field.into(),
            value: value.to_string(),
            allowed: allowed.into(),
        }
    }

    /// The same error with its field named inside `prefix` (`prefix.field`), for a part
    /// validated inside a larger structure.
    pub fn within(mut self, prefix: &str) -> Self {
        self.field = format!("{prefix}.{}", self.field);
        self
    }
}

impl fmt::Display for ParamError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "invalid value for `{}`: {} (allowed: {})",
            self.field, self.value, self.allowed
        )
    }
}

impl std::error::Error for ParamError {}

/// Checks that `value` is finite and lies in the closed interval `[lo, hi]`.
pub fn check_closed(field: &str, value: f64, lo: f64, hi: f64) -> Result<f64, ParamError> {
    if value.is_finite() && value >= lo && value <= hi {
        Ok(value)
    } else {
        Err(ParamError::new(
            field,
            value,
            format!("finite number in [{lo}, {hi}]"),
        ))
    }
}

/// Checks that `value` is finite and strictly positive.
pub fn check_positive(field: &str, value: f64) -> Result<f64, ParamError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(ParamError::new(field, value, "finite number > 0"))
    }
}

/// Checks that `value` is finite and non-negative.
pub fn check_non_negative(field: &str, value: f64) -> Result<f64, ParamError> {
    if value.is_finite() && value >= 0.0 {
        Ok(value)
    } else {
        Err(ParamError::new(field, value, "finite number >= 0"))
    }
}

/// Checks that `value` is finite (any sign).
pub fn check_finite(field: &str, value: f64) -> Result<f64, ParamError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(ParamError::new(field, value, "finite number"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_name_field_value_and_range() {
        let e = check_closed("theta", 1.5, 0.0, 1.0).unwrap_err();
        let s = e.to_string();
        assert!(
            s.contains("theta") && s.contains("1.5") && s.contains("[0, 1]"),
            "{s}"
        );
        assert!(check_positive("h", f64::NAN).is_err());
        assert!(check_positive("h", 0.0).is_err());
        assert!(check_non_negative("gamma", 0.0).is_ok());
        assert!(check_finite("u0", f64::INFINITY).is_err());
    }
}

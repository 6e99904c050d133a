//! `type-mismatch`: a value or argument that does not fit its declared type
//! (defaults and initialisers, numeric ranges, string and sequence bounds,
//! enum values, struct fields, array lengths, and a service `import`/`export`
//! whose type differs from the item it names).

use genom_model::{Code, Diagnostic, Span};

/// `genom-check explain type-mismatch`.
pub const EXPLANATION: &str = r#"A value or argument does not fit its declared type:

- a default or initialiser of the wrong kind (`"fast"` for a `double`, `1.5`
  for a `long`, `TRUE` for a `string`);
- an integer out of the range of its type (`300` for an `octet`, `-1` for an
  `unsigned long`);
- a string or sequence longer than its bound, an array literal with more
  elements than the array;
- an enum value that is not a value of that enum;
- a struct initialiser naming a field the struct does not have;
- a service `import:`/`export:` whose type differs from the data item.

Why it matters: the generated code would not compile, or would silently
truncate the value.

Example:

```
ids limits { octet level := 300; }                 // type-mismatch: 300 is out of range for octet
export out { DEMO_STATE_STR state { pos := 0.0; } } // type-mismatch: no field `pos`
```"#;

/// A value that does not fit `expected`.
pub fn value_mismatch(span: Span, expected: &str, found: &str) -> Diagnostic {
    Diagnostic::new(
        Code::TypeMismatch,
        format!("expected a value of type `{expected}`, found {found}"),
        span,
        format!("not a `{expected}`"),
    )
}

/// An integer out of its type's range.
pub fn out_of_range(span: Span, value: &str, ty: &str, min: i128, max: i128) -> Diagnostic {
    Diagnostic::new(
        Code::TypeMismatch,
        format!("`{value}` is out of range for `{ty}`"),
        span,
        "out of range",
    )
    .with_help(format!("`{ty}` holds values from {min} to {max}"))
}

/// A floating-point value its type cannot hold (infinite, or beyond the
/// magnitude of `float`).
pub fn float_out_of_range(span: Span, value: &str, ty: &str) -> Diagnostic {
    let max = if ty == "float" {
        f64::from(f32::MAX)
    } else {
        f64::MAX
    };
    Diagnostic::new(
        Code::TypeMismatch,
        format!("`{value}` is out of range for `{ty}`"),
        span,
        "out of range",
    )
    .with_help(format!(
        "`{ty}` holds finite values of magnitude up to {max:e}"
    ))
}

/// Too many `unit`s (`elements`, `characters`) for a bound.
pub fn too_long(span: Span, ty: &str, length: usize, bound: u64, unit: &str) -> Diagnostic {
    Diagnostic::new(
        Code::TypeMismatch,
        format!("{length} {unit} do not fit in `{ty}` (at most {bound})"),
        span,
        "too long",
    )
}

/// A field that the struct does not have.
pub fn no_such_field(span: Span, field: &str, ty: &str, help: Option<String>) -> Diagnostic {
    Diagnostic::new(
        Code::TypeMismatch,
        format!("`{ty}` has no field `{field}`"),
        span,
        "unknown field",
    )
    .with_optional_help(help)
}

/// An enum value that is not in the enum.
pub fn not_an_enumerator(span: Span, name: &str, ty: &str, values: &[&str]) -> Diagnostic {
    let list: Vec<String> = values.iter().map(|v| format!("`{v}`")).collect();
    Diagnostic::new(
        Code::TypeMismatch,
        format!("`{name}` is not a value of `{ty}`"),
        span,
        "not a value of this enum",
    )
    .with_help(format!("`{ty}` has {}", list.join(", ")))
}

/// A service import/export declared with another type than the item's.
pub fn declared_type_differs(
    span: Span,
    name: &str,
    declared: &str,
    actual: &str,
    item: Span,
) -> Diagnostic {
    Diagnostic::new(
        Code::TypeMismatch,
        format!("`{name}` is declared `{declared}` here but the data item is `{actual}`"),
        span,
        format!("declared `{declared}`"),
    )
    .with_label(item, format!("`{name}` is `{actual}`"))
}

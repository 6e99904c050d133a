//! Small vocabularies shared by the AST and the resolved model: IDL base
//! types and the kinds of data blocks, services and codels.

use serde::Serialize;

/// IDL base types.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum BaseType {
    /// `double`
    Double,
    /// `float`
    Float,
    /// `short`
    Short,
    /// `long`
    Long,
    /// `long long`
    LongLong,
    /// `unsigned short`
    UShort,
    /// `unsigned long`
    ULong,
    /// `unsigned long long`
    ULongLong,
    /// `char`
    Char,
    /// `boolean`
    Boolean,
    /// `octet`
    Octet,
}

impl BaseType {
    /// The IDL spelling.
    pub fn idl(self) -> &'static str {
        match self {
            BaseType::Double => "double",
            BaseType::Float => "float",
            BaseType::Short => "short",
            BaseType::Long => "long",
            BaseType::LongLong => "long long",
            BaseType::UShort => "unsigned short",
            BaseType::ULong => "unsigned long",
            BaseType::ULongLong => "unsigned long long",
            BaseType::Char => "char",
            BaseType::Boolean => "boolean",
            BaseType::Octet => "octet",
        }
    }

    /// The inclusive range of an integer type, `None` for other types.
    pub fn integer_range(self) -> Option<(i128, i128)> {
        Some(match self {
            BaseType::Short => (i16::MIN.into(), i16::MAX.into()),
            BaseType::Long => (i32::MIN.into(), i32::MAX.into()),
            BaseType::LongLong => (i64::MIN.into(), i64::MAX.into()),
            BaseType::UShort => (0, u16::MAX.into()),
            BaseType::ULong => (0, u32::MAX.into()),
            BaseType::ULongLong => (0, u64::MAX.into()),
            BaseType::Octet => (0, u8::MAX.into()),
            _ => return None,
        })
    }

    /// True for `float` and `double`.
    pub fn is_float(self) -> bool {
        matches!(self, BaseType::Float | BaseType::Double)
    }
}

/// Which kind of lockable data block.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum DataKind {
    /// `ids`: internal data structure.
    Ids,
    /// `export`: produced for other components.
    Export,
    /// `import`: produced by other components.
    Import,
}

impl DataKind {
    /// The keyword.
    pub fn keyword(self) -> &'static str {
        match self {
            DataKind::Ids => "ids",
            DataKind::Export => "export",
            DataKind::Import => "import",
        }
    }
}

/// The kind of a service.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ServiceKind {
    /// Started on request.
    Plain,
    /// `init`: must complete before any other service is accepted.
    Init,
    /// `auto`: started by the component once initialised.
    Auto,
}

impl ServiceKind {
    /// The keyword, empty for plain services.
    pub fn keyword(self) -> &'static str {
        match self {
            ServiceKind::Plain => "",
            ServiceKind::Init => "init",
            ServiceKind::Auto => "auto",
        }
    }
}

/// The kind of a codel.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum CodelKind {
    /// `start codel`
    Start,
    /// `control codel`
    Control,
    /// `exec codel NAME`
    Exec,
    /// `inter codel NAME`
    Inter,
}

impl CodelKind {
    /// The keyword.
    pub fn keyword(self) -> &'static str {
        match self {
            CodelKind::Start => "start",
            CodelKind::Control => "control",
            CodelKind::Exec => "exec",
            CodelKind::Inter => "inter",
        }
    }
}

//! What the parameter table ([`super::PARAMS`]) says about each parameter besides its range:
//! the instruments that read it ([`Reads`]), the group it belongs to ([`ParamGroup`]) and how
//! its value is shown ([`Shown`]). Declared once, in the table's rows; the plugin's editor
//! (which rows to show), its host groups and remote-control pages, and its formatter and
//! parser all read them from there.
//!
//! Plain `Copy` data, any thread.

/// The instruments that read a parameter: a parameter another instrument sets changes nothing
/// in this one's sound ([`super::ParamValues::reads`]; `tests/engine/param_meta.rs` renders every model with each parameter
/// it does not read changed, and checks the output is the same bit for bit).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Reads {
    /// Every model.
    All,
    /// The plates and the single strings: every model but the string networks (the drone and
    /// the sitar with its taraf have their own strings' lengths and hear their bridges, not a
    /// point of a string).
    Bodies,
    /// The plates (gong, cymbal, rectangle).
    Plates,
    /// The circular plates (gong, cymbal).
    CircularPlates,
    /// The rectangular plate.
    RectPlate,
    /// The strings (sitar, tanpura).
    Strings,
    /// The plucked models: the strings, the drone and the sitar with its taraf.
    Plucked,
    /// The sitar (its curved bridge).
    Sitar,
    /// The tanpura drone (its tuning, strings, jivari and cycle).
    Drone,
    /// The sitar with its taraf (the taraf's thaat and strings, the chikari).
    SitarTaraf,
    /// The string networks: the drone and the sitar with its taraf (tuning by ear).
    Networks,
    /// The plates made of the custom material (its elastic constants).
    CustomMaterial,
    /// The plates struck by the force pulse (`exciter` = pulse).
    Pulse,
    /// The plates struck by the mallet (`exciter` = mallet).
    Mallet,
    /// The plates struck by the mallet with the custom head (a factory head brings its own
    /// mass and contact law).
    CustomMallet,
}

/// The group a parameter belongs to: the host's parameter groups and the plugin's
/// remote-control pages, in this order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ParamGroup {
    /// Model, geometry and material.
    ModelAndMaterial,
    /// Modal damping and the release.
    DampingAndRelease,
    /// Strike, mallet and pluck.
    Excitation,
    /// The two output points.
    Pickups,
    /// The string and its bridge contact.
    StringAndBridge,
    /// Modes, rates, scheme, voices and the budgets.
    Quality,
    /// Tuning, expression and the output stage.
    TuningAndOutput,
}

impl ParamGroup {
    /// Every group, in display order.
    pub const ALL: [ParamGroup; 7] = [
        Self::ModelAndMaterial,
        Self::DampingAndRelease,
        Self::Excitation,
        Self::Pickups,
        Self::StringAndBridge,
        Self::Quality,
        Self::TuningAndOutput,
    ];

    /// The group's title (host parameter groups: never renamed, hosts key automation lanes'
    /// folders by it).
    pub const fn title(self) -> &'static str {
        match self {
            Self::ModelAndMaterial => "Model and material",
            Self::DampingAndRelease => "Damping and release",
            Self::Excitation => "Excitation",
            Self::Pickups => "Pickups",
            Self::StringAndBridge => "String and bridge",
            Self::Quality => "Quality",
            Self::TuningAndOutput => "Tuning and output",
        }
    }
}

/// How a parameter's value is shown and typed (the stored value keeps the table's unit).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Shown {
    /// A length in m, shown in µm, mm, cm or m.
    Length,
    /// Young's modulus in Pa, shown in GPa.
    Modulus,
    /// An angle in rad, shown in degrees.
    Angle,
    /// A fraction 0..1, shown in %.
    Percent,
    /// A frequency in Hz, shown in Hz or kHz.
    Frequency,
    /// A time in s, shown in ms or s.
    Time,
    /// A linear density in kg/m, shown in g/m.
    LinearDensity,
    /// A MIDI key, shown as a note name.
    Key,
    /// A count with its singular and plural noun ("1 voice", "4 voices").
    Count(&'static str, &'static str),
    /// The worker threads: 0 reads "all cores".
    Threads,
    /// A budget in its unit (the CPU budget in cores, the memory cap in MB): 0 reads "auto"
    /// (the engine's share of the machine's).
    Auto(&'static str),
    /// A plain number with a fixed unit text (possibly empty); enumerations show their names.
    Plain(&'static str),
}

//! The configurations a sequence runs under: how the layer is set up (tracking, trigger
//! widening, speed-ups, monitor), what the base subscriber asks for, and which checks
//! apply (see the module documentation of `tests/fuzz_operations.rs`).

use rapier_contact_graph::coherence::Tracking;
use rapier_contact_graph::speedups::SpeedUps;
use rapier_contact_graph::KindSet;

/// Whether the layer recovers from Rapier steps it did not see (the unseen-step
/// witness of a few awake bodies). Without it, steps the layer does not see and a second layer taking turns failed
/// under touching tracking ("Rapier pair of nodes 3–4 has no edge"), and the generator
/// made them only under the proximity configuration (where the layer reads every pair
/// each step). `FUZZ_UNSEEN=0` turns them off everywhere, `FUZZ_UNSEEN=1` on.
pub const UNSEEN_STEPS_RECOVERED: bool = true;

/// A preset of the speed-ups (`src/speedups/config.rs`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Preset {
    /// `SpeedUps::default()`: the contact graph with Rapier's caching kept.
    Default,
    /// `SpeedUps::contact_graph()`: the paper's groups and sleepy bodies, caching off.
    ContactGraph,
    /// `SpeedUps::reliable_sleep()`: piles held still (fixation), with caching.
    ReliableSleep,
    /// `SpeedUps::papers_fastest()`: the paper's fastest (`C--ZDSF`).
    PapersFastest,
}

impl Preset {
    pub fn speedups(self) -> SpeedUps {
        match self {
            Preset::Default => SpeedUps::default(),
            Preset::ContactGraph => SpeedUps::contact_graph(),
            Preset::ReliableSleep => SpeedUps::reliable_sleep(),
            Preset::PapersFastest => SpeedUps::papers_fastest(),
        }
    }
}

/// How a sequence runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Config {
    /// What a user gets: the layer's defaults (touching tracking, Rapier's own sensor
    /// types) and a base subscriber to `KindSet::COLLISION_EVENTS` (contact and
    /// sensor start / stop). Observe-only: checked against a plain twin world.
    Touching,
    /// Proximity tracking: the base subscriber asks for every kind (so every pair is
    /// read each step), sensors widened. Observe-only: checked against a twin.
    Proximity,
    /// A preset of the speed-ups with the monitor repairing, under the default
    /// tracking; the base subscriber asks for every kind touching tracking delivers
    /// (monitor events included).
    SpeedUps(Preset),
    /// The modes of the regression tests written before the configurations
    /// (`harness::run`): `touching` sets touching tracking with a base subscriber to
    /// every kind but `KindSet::NEEDS_EVERY_PAIR`, sensors as the user built them;
    /// otherwise a base subscriber to every kind, sensors widened. Speed-ups only
    /// through `Op::SpeedUps`.
    Legacy { touching: bool },
}

impl Config {
    /// The configurations the property runs, one test each.
    pub const ALL: [Config; 6] = [
        Config::Touching,
        Config::Proximity,
        Config::SpeedUps(Preset::Default),
        Config::SpeedUps(Preset::ContactGraph),
        Config::SpeedUps(Preset::ReliableSleep),
        Config::SpeedUps(Preset::PapersFastest),
    ];

    /// What the base subscriber (the contract checker's) asks for.
    pub fn base(self) -> KindSet {
        match self {
            Config::Touching => KindSet::COLLISION_EVENTS,
            Config::Proximity | Config::Legacy { touching: false } => KindSet::ALL,
            Config::SpeedUps(_) | Config::Legacy { touching: true } => {
                KindSet::ALL.without(KindSet::NEEDS_EVERY_PAIR)
            }
        }
    }

    /// Whether sensors are widened (`set_trigger_widening`).
    pub fn widening(self) -> bool {
        matches!(self, Config::Proximity | Config::Legacy { touching: false })
    }

    /// The tracking asked for at the start (`None`: the layer's default).
    pub fn tracking(self) -> Option<Tracking> {
        match self {
            Config::Legacy { touching: true } => Some(Tracking::Touching),
            _ => None,
        }
    }

    /// The speed-ups set at the start.
    pub fn speedups(self) -> Option<SpeedUps> {
        match self {
            Config::SpeedUps(p) => Some(p.speedups()),
            _ => None,
        }
    }

    /// Whether the monitor repairs.
    pub fn monitor(self) -> bool {
        matches!(self, Config::SpeedUps(_))
    }

    /// Whether the layer starts observe-only (no speed-ups, no monitor): then the
    /// world is compared bit for bit with a plain twin.
    pub fn observe_only(self) -> bool {
        !matches!(self, Config::SpeedUps(_))
    }

    /// Whether touching tracking must be in effect on some steps of a run (the
    /// property asserts it over the run), or on none.
    pub fn expects_touching(self) -> Option<bool> {
        match self {
            Config::Touching | Config::SpeedUps(_) => Some(true),
            Config::Proximity => Some(false),
            Config::Legacy { .. } => None,
        }
    }

    /// Whether sequences of this configuration may hold steps the layer does not see
    /// ([`super::Op::Unseen`]) and a second layer ([`super::Op::Second`]); see
    /// [`UNSEEN_STEPS_RECOVERED`].
    pub fn unseen_steps(self) -> bool {
        match std::env::var("FUZZ_UNSEEN").as_deref() {
            Ok("1") => return true,
            Ok("0") => return false,
            _ => {}
        }
        UNSEEN_STEPS_RECOVERED || self == Config::Proximity
    }

    /// The test's name for the configuration.
    pub fn name(self) -> &'static str {
        match self {
            Config::Touching => "touching",
            Config::Proximity => "proximity",
            Config::SpeedUps(Preset::Default) => "speedups_default",
            Config::SpeedUps(Preset::ContactGraph) => "speedups_contact_graph",
            Config::SpeedUps(Preset::ReliableSleep) => "speedups_reliable_sleep",
            Config::SpeedUps(Preset::PapersFastest) => "speedups_papers_fastest",
            Config::Legacy { touching: true } => "legacy_touching",
            Config::Legacy { touching: false } => "legacy_proximity",
        }
    }
}

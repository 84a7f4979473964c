//! The step's workspace: the buffers and derived data a step writes before it reads them,
//! kept apart from the world's persistent state (rapier's split: "the pipeline only contains
//! temporary buffers and can be dropped at any time"). A checkpoint leaves it out; a world
//! read back from one starts with an empty workspace and continues bit-identically, because
//! every entry is either rebuilt before use or flagged stale (`packed_fresh`,
//! `packed_current` false, an empty clump trig cache, fragments found again).

use crate::clump;
use crate::contact::disc_disc::Slots;
use crate::damping::FragmentDamping;
use crate::integrate::Moved;
use crate::team::Threads;

/// What [`crate::World::step`] works in.
#[derive(Clone, Debug, Default)]
pub(crate) struct StepWorkspace {
    /// The disc–disc pass's work arrays: partner-side force slots, own-pair sums, the block
    /// scratch, the split of the discs between threads, and the packed disc records with
    /// their freshness flags (written by the integrator for the next pass).
    pub slots: Slots,
    /// The integration pass's per-part results (kinetic energy, damping, boundary work).
    pub parts: Vec<Moved>,
    /// The clumps' last `sin_cos` (derived data, rebuilt on demand).
    pub clump_trig: clump::TrigCache,
    /// The thread counts of this step, read from the rayon pool at its start (the one read
    /// of the step; the team reads its own size where it dispatches).
    pub threads: Threads,
    /// Local damping in the fragment frame: the fragments and this step's damping forces
    /// (used only when `Params::damping_frame` is `Fragment`).
    pub frag: FragmentDamping,
}

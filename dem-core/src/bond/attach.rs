//! Putting bonds into a [`World`].
//!
//! Bonds store disc *indices*, and [`World::try_new`] may reorder the discs in space. So bonds
//! built on a state before the world exists are carried over by disc id: [`world_with_bonds`]
//! builds the world, remaps the bonds to the new indices, attaches them and refreshes the time
//! step (which then includes the bond stiffness). Bonds made on `world.state` after the world
//! exists use its current indices; attach them with [`attach`].

use super::Bonds;
use crate::contact::ContactLaws;
use crate::params::Params;
use crate::pipeline::{World, WorldError};
use crate::state::State;

/// Build a world from `state` with `bonds` (made on `state`'s indices) and the contact offsets
/// `(id_a, id_b, g0)` of overlapping bonded pairs (see [`crate::bonded_clump`]).
pub fn world_with_bonds(
    state: State,
    params: Params,
    laws: ContactLaws,
    mut bonds: Bonds,
    offsets: &[(u32, u32, f64)],
) -> Result<World, WorldError> {
    let ids = state.discs.id.clone();
    let mut w = World::try_new(state, params, laws)?;
    let new_of_old: Vec<u32> = ids
        .iter()
        .map(|&id| w.index_of_id(id).map_or(u32::MAX, |k| k as u32))
        .collect();
    if !new_of_old.iter().enumerate().all(|(k, &n)| n as usize == k) {
        bonds.remap(&new_of_old);
    }
    for &(a, b, g0) in offsets {
        w.set_contact_offset(a, b, g0);
    }
    attach(&mut w, bonds);
    Ok(w)
}

/// Attach bonds made on `world.state`'s current indices and refresh the world (neighbour list,
/// time step with the bond stiffness).
pub fn attach(world: &mut World, bonds: Bonds) {
    world.bonds = Some(bonds);
    world.refresh();
}

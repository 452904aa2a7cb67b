//! CGA `scatter(surface | volume | scope, n, uniform | gaussian [, mean [, stddev]]) { … }`:
//! `n` point shapes (no geometry, a scope of size 0) at random places of the shape, drawn from
//! its random stream, each derived with the block's operations (usually an insert).

use shapegram_geom::{DVec3, Scope, scatter::Sampler};
use shapegram_syntax::Span;

use super::Fallible;
use super::footprint::grown_axes;
use super::machine::{Engine, Work};
use crate::error::DeriveError;
use crate::ops::{ScatterDomain, ScatterSpec};
use crate::program::CKind;
use crate::shape::{Geometry, State};
use crate::value::Value;

/// Draws a gaussian point may take before the last one is kept whatever its weight.
const GAUSSIAN_TRIES: usize = 10_000;

/// Draws a point in a volume may take before it falls back to the surface.
const VOLUME_TRIES: usize = 1_000;

impl<'p> Engine<'p> {
    /// The points of `scatter`, each a child shape: on the surface, its scope's y along the
    /// surface's normal (x kept as far as it can be); elsewhere, the shape's axes. `volume` on
    /// geometry that is not closed scatters on its surface.
    pub(super) fn scatter(
        &mut self,
        state: &mut State,
        spec: &'p ScatterSpec,
        span: Span,
        args: &[Value],
        out: &mut Vec<Work>,
    ) -> Fallible<()> {
        let n = self.ev.number(&spec.count, state, args)?;
        if !(n >= 0.0 && n.is_finite()) {
            return Err(DeriveError::at(
                format!("scatter's count must be 0 or more, not {n}"),
                spec.count.span,
            ));
        }
        let size = state.scope.size;
        let sigma = match &spec.gaussian {
            Some((_, Some(e))) => match &e.kind {
                CKind::Relative(inner) => size * self.ev.number(inner, state, args)?,
                _ => DVec3::splat(self.ev.number(e, state, args)?),
            },
            _ => size * 0.16,
        };
        let mean = spec
            .gaussian
            .as_ref()
            .map(|(at, _)| DVec3::from_array(*at) * size);
        let world = state.geometry.world_mesh(&state.scope);
        let sampler = world.as_ref().map(Sampler::new);
        let domain = match (spec.domain, &sampler) {
            (ScatterDomain::Scope, _) => ScatterDomain::Scope,
            (ScatterDomain::Volume, Some(s)) if s.is_closed() => ScatterDomain::Volume,
            (_, Some(s)) if s.area() > 0.0 => ScatterDomain::Surface,
            _ => ScatterDomain::Scope,
        };
        let scope = state.scope;
        let total = n.round() as u64;
        for _ in 0..total {
            let mut tries = 0;
            let (point, normal) = loop {
                tries += 1;
                let candidate = match domain {
                    ScatterDomain::Scope => (uniform_in(&scope, state), None),
                    ScatterDomain::Volume => {
                        let sampler = sampler.as_ref().expect("a closed mesh");
                        let inside = (0..VOLUME_TRIES)
                            .map(|_| uniform_in(&scope, state))
                            .find(|&p| sampler.contains(p));
                        match inside {
                            Some(p) => (p, None),
                            None => on_surface(sampler, state),
                        }
                    }
                    ScatterDomain::Surface => {
                        on_surface(sampler.as_ref().expect("a surface"), state)
                    }
                };
                let Some(mean) = mean else { break candidate };
                // Rejection: keep the point with the gaussian's weight there.
                let d = scope.to_local(candidate.0) - mean;
                let z = DVec3::select(sigma.cmpgt(DVec3::ZERO), d / sigma, DVec3::ZERO);
                let weight = (-0.5 * z.length_squared()).exp();
                if state.rng.next_f64() < weight || tries >= GAUSSIAN_TRIES {
                    break candidate;
                }
            };
            let axes = match normal {
                Some(up) => grown_axes(&scope, up),
                None => scope.axes,
            };
            let mut child = state.spawn();
            child.scope = Scope::new(point, axes, DVec3::ZERO);
            child.geometry = Geometry::Empty;
            self.admit(&mut child, span)?;
            self.run_stmts(&spec.body, &mut child, args, out)?;
        }
        Ok(())
    }
}

/// A uniform point of the scope's box.
fn uniform_in(scope: &Scope, state: &mut State) -> DVec3 {
    let r = DVec3::new(
        state.rng.next_f64(),
        state.rng.next_f64(),
        state.rng.next_f64(),
    );
    scope.to_world(r * scope.size)
}

/// A uniform point of the surface, with its normal.
fn on_surface(sampler: &Sampler, state: &mut State) -> (DVec3, Option<DVec3>) {
    let r = [
        state.rng.next_f64(),
        state.rng.next_f64(),
        state.rng.next_f64(),
    ];
    match sampler.on_surface(r) {
        Some((p, normal)) => (p, Some(normal)),
        None => (DVec3::ZERO, None),
    }
}

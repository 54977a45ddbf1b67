//! Where a SEAS output's nodes are: the position along the fault of every frictional
//! node, the stations' nodes, the profile's nodes, the vertices of the stations off the fault.

use rsf::Model;

use crate::error::{invalid, Result};
use crate::setup::SeasSetup;
use crate::text::positions_row;

/// Where the output's nodes are: depths of the frictional nodes, stations, profile.
pub(super) struct Layout {
    pub(super) depths: Vec<f64>,
    /// Frictional node of each station.
    pub(super) stations: Vec<usize>,
    pub(super) profile: Vec<usize>,
    /// Vertex of each station off the fault.
    pub(super) surface: Vec<usize>,
    /// Components of the field (the stations off the fault write each).
    pub(super) components: usize,
}

impl Layout {
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named
    /// `surface_stations` for a position of another dimension than the model's or not
    /// finite, a name that is empty, not one line or repeated.
    pub(super) fn new<const D: usize, const C: usize>(
        model: &Model<D, C>,
        setup: &SeasSetup,
    ) -> Result<Self> {
        let fb = &model.frictional_boundary;
        let sign = if setup.depth_down { 1.0 } else { -1.0 };
        let depths: Vec<f64> = fb
            .nodes
            .iter()
            .map(|&p| {
                setup
                    .layout
                    .along(sign * model.vertices[p][setup.depth_axis])
            })
            .collect();
        let nearest = |d: f64| {
            (0..depths.len())
                .min_by(|&i, &j| (depths[i] - d).abs().total_cmp(&(depths[j] - d).abs()))
                .unwrap_or(0)
        };
        let stations = setup.stations.iter().map(|(_, d)| nearest(*d)).collect();
        // Profile nodes: by depth from the surface, at least `profile_spacing` apart.
        let mut order: Vec<usize> = (0..depths.len()).collect();
        order.sort_by(|&i, &j| depths[i].total_cmp(&depths[j]));
        let mut profile = Vec::new();
        let mut next = f64::NEG_INFINITY;
        for k in order {
            if depths[k] >= next - 1e-9 * setup.profile_spacing {
                profile.push(k);
                next = depths[k] + setup.profile_spacing;
            }
        }
        let mut surface = Vec::with_capacity(setup.surface_stations.len());
        for (i, st) in setup.surface_stations.iter().enumerate() {
            let bad = |why: String| invalid("surface_stations", format!("station {i}: {why}"));
            if st.position.len() != D || st.position.iter().any(|x| !x.is_finite()) {
                return Err(bad(format!(
                    "position {:?} must have {D} finite coordinates",
                    st.position
                )));
            }
            if st.name.trim().is_empty()
                || st.name.contains(['\n', '\r', '/', '\\'])
                || setup.surface_stations[..i]
                    .iter()
                    .any(|o| o.name == st.name)
                || setup.stations.iter().any(|(n, _)| *n == st.name)
            {
                return Err(bad(format!(
                    "name `{}` must be one line, a file name, and not repeated",
                    rsf_numeric::excerpt(&st.name)
                )));
            }
            let distance = |p: usize| {
                model.vertices[p]
                    .iter()
                    .zip(&st.position)
                    .map(|(a, b)| (a - b) * (a - b))
                    .sum::<f64>()
            };
            let nearest = (0..model.vertices.len())
                .min_by(|&a, &b| distance(a).total_cmp(&distance(b)))
                .unwrap_or(0);
            surface.push(match &model.internal_fault {
                Some(f) => f.copy_on(nearest, st.side),
                None => nearest,
            });
        }
        Ok(Self {
            depths,
            stations,
            profile,
            surface,
            components: C,
        })
    }

    /// The line of `devol.dat` after its `#` lines: `0 0` and the profile's depths.
    pub(super) fn profile_first_row(&self) -> String {
        positions_row(self.profile.iter().map(|&k| self.depths[k]))
    }
}

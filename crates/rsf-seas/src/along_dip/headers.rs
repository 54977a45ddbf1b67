//! The files of an output along dip as [`FileLayout`]s: an on-fault station (the columns of
//! BP1 or BP3), a station off the fault (a field of one or more components), a profile of a
//! quantity along the fault's depth or down-dip distance.

use crate::setup::{ProfileQuantity, SeasSetup};
use crate::text::{FileLayout, Positions};

/// An on-fault station at `depth` (m; its position along the fault, depth or down-dip
/// distance): the layout's columns.
pub(super) fn station(setup: &SeasSetup, depth: f64) -> FileLayout {
    FileLayout::new(
        format!(
            "on fault, {} km {}",
            depth / 1e3,
            setup.layout.coordinate().0
        ),
        setup.layout.station_columns(),
    )
}

/// A profile file of `quantity` (`devol.dat`, `slip.dat`, `shear_stress.dat`,
/// `normal_stress.dat`): time, the maximum slip rate, the quantity at every position of the
/// first data row (`0 0` and the positions).
pub(super) fn profile(setup: &SeasSetup, quantity: ProfileQuantity) -> FileLayout {
    let (word, symbol) = setup.layout.coordinate();
    let plural = if word == "depth" {
        "depths"
    } else {
        "down-dip distances"
    };
    FileLayout {
        location: format!(
            "{} profiles along the fault's {word} {symbol}",
            quantity.field()
        ),
        columns: vec![
            ("t".into(), "Time (s)".into()),
            (
                "max_slip_rate".into(),
                "Max slip rate on the fault (log10 m/s)".into(),
            ),
            (
                quantity.field().into(),
                format!(
                    "{} at the {plural} {symbol} (m) of the first data row, one column per {word}",
                    quantity.description()
                ),
            ),
        ],
        profile: Some(Positions {
            words: format!("{plural} {symbol}"),
            coordinate: symbol.into(),
            name_per_line: false,
        }),
    }
}

/// A station off the fault at `position` (m) with a field of `components` components:
/// `t`, `disp_1 …`, `vel_1 …` (the component along `setup.depth_axis` vertical, positive
/// down, for a vector field).
pub(super) fn surface(setup: &SeasSetup, position: &[f64], components: usize) -> FileLayout {
    let at = position
        .iter()
        .map(|x| format!("{} km", x / 1e3))
        .collect::<Vec<_>>()
        .join(", ");
    FileLayout {
        location: format!("off fault, ({at})"),
        columns: surface_columns(components, setup.depth_axis),
        profile: None,
    }
}

/// The columns of a station off the fault with a field of `components` components: `t`,
/// `disp_1 …`, `vel_1 …`, with their descriptions (`depth_axis` the vertical component,
/// positive down, for a vector field).
fn surface_columns(components: usize, depth_axis: usize) -> Vec<(String, String)> {
    let what = |c: usize| match components {
        1 => "the field's component".to_owned(),
        _ if c == depth_axis => "vertical, positive down".to_owned(),
        2 => "horizontal".to_owned(),
        _ => format!("along x{}", c + 1),
    };
    let column = |name: &str, unit: &str, c: usize| {
        (
            format!("{}_{}", name, c + 1),
            format!(
                "{} {}, {} ({unit})",
                if name == "disp" {
                    "Displacement"
                } else {
                    "Velocity"
                },
                c + 1,
                what(c)
            ),
        )
    };
    std::iter::once(("t".to_owned(), "Time (s)".to_owned()))
        .chain((0..components).map(|c| column("disp", "m", c)))
        .chain((0..components).map(|c| column("vel", "m/s", c)))
        .collect()
}

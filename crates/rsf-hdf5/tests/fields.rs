//! HDF5 fields: a 3-D slider run writes VTU frames and the HDF5 file side by side; read
//! back (vtkio, hdf5-metno) the file's mesh and every frame's fields equal the VTU frames'
//! values bit for bit, the time axis is the frames', each field names its unit, and the
//! Xdmf index references datasets that exist with the dimensions it declares. A resume cuts
//! the frames after the checkpoint, once the file shows it holds the checkpoint's run.

use rsf::observe::{Every, FileMode, Interval, VtuFrames};
use rsf_hdf5::Hdf5Fields;
use rsf_scenes::{Slider3dScene, SliderScene};

mod common;
use common::{bits, temp_dir, vtu_field};

/// The fields and their components, written out here (the writers take them from
/// `rsf::observe::POINT_FIELDS`).
const FIELDS: [(&str, usize); 8] = [
    ("displacement", 3),
    ("velocity", 3),
    ("slip_rate", 1),
    ("state_alpha", 1),
    ("slip", 3),
    ("shear_traction", 1),
    ("normal_traction", 1),
    ("fault", 1),
];

fn scene() -> Slider3dScene {
    Slider3dScene {
        slider: SliderScene {
            level: 0,
            steps: 100,
            // Fast loading: Γ_F slides within the few steps, so the fields vary.
            loading_velocity_m_per_s: 2e-2,
            ..SliderScene::default()
        },
        ..Slider3dScene::default()
    }
}

#[test]
fn hdf5_fields_equal_the_vtu_frames_and_the_xdmf_index_references_them() {
    let dir = temp_dir("hdf5-fields");
    let h5 = dir.join("fields.h5");
    let mut sim = scene().build().unwrap();
    let mut frames = Every::new(
        Interval::Steps(2),
        VtuFrames::new(dir.join("frames"), FileMode::Create).unwrap(),
    )
    .unwrap();
    let mut fields = Every::new(
        Interval::Steps(2),
        Hdf5Fields::new(&h5, FileMode::Create).unwrap(),
    )
    .unwrap();
    sim.run(6, &mut [&mut frames, &mut fields]).unwrap();
    drop(fields);
    let m = sim.model();
    let n = m.num_nodes();
    let file = hdf5::File::open(&h5).expect("an HDF5 file");
    let points: Vec<f64> = file.dataset("mesh/points").unwrap().read_raw().unwrap();
    assert_eq!(
        points,
        m.vertices.iter().flatten().copied().collect::<Vec<_>>()
    );
    let cells: Vec<u64> = file.dataset("mesh/cells").unwrap().read_raw().unwrap();
    assert_eq!(cells, m.cells.iter().map(|&c| c as u64).collect::<Vec<_>>());
    assert_eq!(
        file.dataset("mesh/cells").unwrap().shape(),
        [m.cells.len() / 4, 4]
    );
    let steps: Vec<u64> = file.dataset("step").unwrap().read_raw().unwrap();
    assert_eq!(steps, [2, 4, 6]);
    let times: Vec<f64> = file.dataset("time").unwrap().read_raw().unwrap();
    let tau = scene().slider.tau();
    for (t, s) in times.iter().zip(&steps) {
        assert!((t - tau * *s as f64).abs() <= 1e-12, "time {t} of step {s}");
    }
    let mut nonzero = 0;
    for (name, c) in FIELDS {
        let d = file.dataset(&format!("fields/{name}")).unwrap();
        let shape: Vec<usize> = if c == 3 { vec![3, n, 3] } else { vec![3, n] };
        assert_eq!(d.shape(), shape, "{name}");
        let unit: hdf5::types::VarLenUnicode = d.attr("unit").unwrap().read_scalar().unwrap();
        let want = rsf::observe::POINT_FIELDS
            .iter()
            .find(|f| f.0 == name)
            .unwrap()
            .2;
        assert_eq!(unit.as_str(), want, "{name}");
        let all: Vec<f64> = d.read_raw().unwrap();
        for (i, s) in steps.iter().enumerate() {
            let vtu = vtu_field(&dir.join(format!("frames/frame_{s:06}.vtu")), name);
            let frame = &all[i * n * c..(i + 1) * n * c];
            assert_eq!(bits(frame), bits(&vtu), "{name} at step {s}");
            nonzero += frame.iter().filter(|x| x.is_finite() && **x != 0.0).count();
        }
    }
    assert!(nonzero > 0, "the fields are not all zero");
    // The names the field `fault` indexes: the model's, as a JSON list (the slider's one
    // frictional boundary).
    let names: hdf5::types::VarLenUnicode = file
        .dataset("fields/fault")
        .unwrap()
        .attr("fault_names")
        .unwrap()
        .read_scalar()
        .unwrap();
    let want: Vec<String> = m
        .frictional_boundary
        .fault_names
        .iter()
        .map(|n| format!("\"{n}\""))
        .collect();
    assert_eq!(names.as_str(), format!("[{}]", want.join(",")));
    // The index: every HDF reference names an existing dataset with its dimensions.
    let xmf = std::fs::read_to_string(dir.join("fields.xmf")).expect("the Xdmf index");
    // The index's times are `/time`'s, bit for bit and in order (ParaView orders the
    // frames by them), and frame i reads slab i of every field.
    let index_times: Vec<f64> = xmf
        .split("<Time Value=\"")
        .skip(1)
        .map(|r| r.split_once('"').expect("a quoted time").0.parse().unwrap())
        .collect();
    assert_eq!(bits(&index_times), bits(&times));
    for (i, frame) in xmf.split("<Grid Name=\"frame ").skip(1).enumerate() {
        let (number, rest) = frame.split_once('"').expect("a frame number");
        assert_eq!(number.parse::<usize>().unwrap(), i);
        let slabs: Vec<&str> = rest
            .split("Format=\"XML\">")
            .skip(1)
            .map(|s| s.split_once(' ').expect("a slab start").0)
            .collect();
        assert_eq!(slabs.len(), FIELDS.len(), "frame {i}");
        assert!(
            slabs.iter().all(|s| s.parse::<usize>() == Ok(i)),
            "frame {i} reads slabs {slabs:?}"
        );
    }
    let mut references = 0;
    for item in xmf.split("<DataItem").skip(1) {
        let Some((_, rest)) = item.split_once("Format=\"HDF\">") else {
            continue;
        };
        let dims: Vec<usize> = item
            .split_once("Dimensions=\"")
            .and_then(|(_, r)| r.split_once('"'))
            .map(|(d, _)| d.split(' ').map(|x| x.parse().unwrap()).collect())
            .expect("Dimensions");
        let (file_name, dataset) = rest
            .split_once('<')
            .map(|(r, _)| r)
            .and_then(|r| r.split_once(":/"))
            .expect("FILE:/DATASET");
        assert_eq!(file_name, "fields.h5");
        let d = file
            .dataset(dataset)
            .unwrap_or_else(|_| panic!("no dataset {dataset}"));
        assert_eq!(d.shape(), dims, "{dataset}");
        references += 1;
    }
    assert_eq!(references, 3 * (2 + FIELDS.len()));
    assert!(xmf.matches("TopologyType=\"Tetrahedron\"").count() == 3);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_resumed_hdf5_file_equals_the_uninterrupted_runs() {
    let dir = temp_dir("hdf5-resume");
    let (whole, part) = (dir.join("whole.h5"), dir.join("part.h5"));
    let mut sim = scene().build().unwrap();
    let mut fields = Hdf5Fields::new(&whole, FileMode::Create).unwrap();
    sim.run(4, &mut [&mut fields]).unwrap();
    drop(fields);
    // A run checkpointed at step 2 and stopped after step 3, resumed from the checkpoint.
    let mut first = scene().build().unwrap();
    let mut fields = Hdf5Fields::new(&part, FileMode::Create)
        .unwrap()
        .fingerprint(scene().fingerprint());
    first.run(2, &mut [&mut fields]).unwrap();
    let checkpoint = rsf::Stepping::checkpoint(&first);
    first.run(1, &mut [&mut fields]).unwrap();
    drop(fields);
    let steps = |path: &std::path::Path| -> Vec<u64> {
        let f = hdf5::File::open(path).unwrap();
        f.dataset("step").unwrap().read_raw().unwrap()
    };
    assert_eq!(steps(&part), [1, 2, 3]);
    // The file proves it holds the checkpoint's run (issue 87), the file byte-identical
    // after each refusal: a checkpoint of another run's parameters (faster loading) by the
    // fingerprint the file recorded; one of another state at the same step and time (the
    // run's own fingerprint, another α) by the frame's state; one of a step without a frame.
    let bytes = std::fs::read(&part).unwrap();
    let other_scene = Slider3dScene {
        slider: SliderScene {
            loading_velocity_m_per_s: 3e-2,
            ..scene().slider
        },
        ..scene()
    };
    let mut other = other_scene.build().unwrap();
    other.run(2, &mut []).unwrap();
    let mut other = rsf::Stepping::checkpoint(&other);
    other.fingerprint = other_scene.fingerprint();
    let e = Hdf5Fields::continue_run(&part, &other, &[])
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("another run") && e.contains("loading_velocity"),
        "{e}"
    );
    let mut shifted = checkpoint.clone();
    shifted.fingerprint = scene().fingerprint();
    shifted.state.alpha[0] += 1e-9;
    let e = Hdf5Fields::continue_run(&part, &shifted, &[])
        .unwrap_err()
        .to_string();
    assert!(e.contains("another state"), "{e}");
    let mut early = shifted.clone();
    early.state.step = 7;
    let e = Hdf5Fields::continue_run(&part, &early, &[])
        .unwrap_err()
        .to_string();
    assert!(e.contains("no frame of the checkpoint's step 7"), "{e}");
    let mut later = checkpoint.clone();
    later.fingerprint = scene().fingerprint();
    later.state.time *= 1.0 + 1e-12;
    let e = Hdf5Fields::continue_run(&part, &later, &[])
        .unwrap_err()
        .to_string();
    assert!(e.contains("another run") && e.contains("t = "), "{e}");
    assert_eq!(std::fs::read(&part).unwrap(), bytes);
    let mut checkpoint = checkpoint;
    checkpoint.fingerprint = scene().fingerprint();
    let mut resumed = scene().build().unwrap();
    rsf::Stepping::restore(&mut resumed, &checkpoint).unwrap();
    let mut fields = Hdf5Fields::continue_run(&part, &checkpoint, &[]).unwrap();
    resumed.run(2, &mut [&mut fields]).unwrap();
    drop(fields);
    let (a, b) = (
        hdf5::File::open(&whole).unwrap(),
        hdf5::File::open(&part).unwrap(),
    );
    assert_eq!(steps(&part), [1, 2, 3, 4]);
    assert_eq!(steps(&whole), steps(&part));
    for name in
        std::iter::once("time".to_owned()).chain(FIELDS.iter().map(|(f, _)| format!("fields/{f}")))
    {
        let x: Vec<f64> = a.dataset(&name).unwrap().read_raw().unwrap();
        let y: Vec<f64> = b.dataset(&name).unwrap().read_raw().unwrap();
        assert_eq!(bits(&x), bits(&y), "{name}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

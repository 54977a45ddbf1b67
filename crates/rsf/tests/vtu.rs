//! VTU frames for ParaView: files are written during the run and read back with vtkio.
#![cfg(feature = "vtk")]

use rsf::{Observer, SliderScene, VtuFrames};

#[test]
fn frames_and_index_are_written_and_readable() {
    let dir = std::env::temp_dir().join(format!("rsf-vtu-{}", std::process::id()));
    let scene = SliderScene {
        level: 1,
        steps: 100,
        ..SliderScene::default()
    };
    let mut sim = scene.build().unwrap();
    let mut frames = VtuFrames::create(&dir, 2).unwrap();
    sim.run(4, &mut [&mut frames as &mut dyn Observer<2>])
        .unwrap();
    for step in [2, 4] {
        let path = dir.join(format!("frame_{step:06}.vtu"));
        let vtk = vtkio::Vtk::import(&path).expect("frame is valid VTK XML");
        let vtkio::model::DataSet::UnstructuredGrid { pieces, .. } = vtk.data else {
            panic!("not an unstructured grid")
        };
        let piece = pieces[0].load_piece_data(None).unwrap();
        assert_eq!(piece.num_points(), sim.model().vertices.len());
        assert_eq!(piece.data.point.len(), 2);
    }
    let pvd = std::fs::read_to_string(dir.join("frames.pvd")).unwrap();
    assert_eq!(pvd.matches("<DataSet ").count(), 2);
    std::fs::remove_dir_all(&dir).ok();
}

//! `vbrain slice`: radiology-style figures of a set's MRI with organ outlines (issue: sectional
//! anatomy). A synthetic volume's bright block lands where its voxels are; the default brain's
//! left thalamus sits on the image's right in radiological display and on its left in neurological.

use crate::cli::{brain, json, two_blobs, vbrain, write_nifti};
use std::path::Path;

/// The image pixel of world point (h, v) on the plane, from the command's JSON report.
fn pixel(report: &serde_json::Value, h: f64, v: f64, mirrored: bool) -> (u32, u32) {
    let f = |k: &str| report[k].as_f64().unwrap();
    let (c, mm) = (&report["centre_mm"], f("mm_per_pixel"));
    let sign = if mirrored { -1.0 } else { 1.0 };
    let x = sign * (h - c[0].as_f64().unwrap()) / mm + f("width") / 2.0;
    let y = -(v - c[1].as_f64().unwrap()) / mm + f("height") / 2.0;
    (x as u32, y as u32)
}

fn grey(path: &Path, (x, y): (u32, u32)) -> [u8; 3] {
    let image = image::open(path).unwrap().to_rgb8();
    image.get_pixel(x, y).0
}

/// A set of two blocks (import of [`two_blobs`]) with an MRI on the same 2 mm grid: 100
/// everywhere, 1000 in voxels x 5..9, y 6..9, z 6..9, inside the first block.
fn set_with_mri(dir: &Path) -> String {
    let vol = two_blobs(dir, "seg.nii");
    let csv = dir.join("labels.csv");
    std::fs::write(&csv, "index,name\n17,Left part\n53,Right part\n").unwrap();
    let set = dir.join("set");
    let s = set.display().to_string();
    json(&vbrain(&["import", vol.to_str().unwrap(), "--labels", csv.to_str().unwrap(), "--out", &s, "--json"]));
    let (nx, ny, nz) = (24, 16, 16);
    let mut values = vec![100i16; nx * ny * nz];
    for z in 6..9 {
        for y in 6..9 {
            for x in 5..9 {
                values[x + nx * (y + ny * z)] = 1000;
            }
        }
    }
    write_nifti(&set.join("mri.nii"), [nx, ny, nz], &values);
    let manifest = set.join("organset.json");
    let mut m: serde_json::Value = serde_json::from_slice(&std::fs::read(&manifest).unwrap()).unwrap();
    m["mri"] = "mri.nii".into();
    std::fs::write(&manifest, serde_json::to_vec_pretty(&m).unwrap()).unwrap();
    s
}

#[test]
fn a_bright_voxel_block_lands_where_its_voxels_are() {
    let dir = tempfile::tempdir().unwrap();
    let set = set_with_mri(dir.path());
    let out = dir.path().join("ax.png");
    // The grid: x = 40 - 2i, y = 2j - 20, z = 2k - 10; the block's centres span x 24..30,
    // y -8..-4, z 2..6. Slice through its middle row of voxels, z = 4.
    let report = json(&vbrain(&[
        "slice",
        &set,
        "--plane",
        "axial=4",
        "--window",
        "1,0.5",
        "--out",
        out.to_str().unwrap(),
        "--json",
    ]));
    assert_eq!(report["mri"], true);
    let bright = grey(&out, pixel(&report, 27.0, -6.0, true));
    let dim = grey(&out, pixel(&report, 27.0, 0.0, true));
    assert!(bright[0] > 200, "the block is bright: {bright:?}");
    assert!(dim[0] < 100, "beside it the volume is dim: {dim:?}");
    // Radiological: x = 27 (the patient's right) is on the image's left half.
    assert!(pixel(&report, 27.0, -6.0, true).0 < report["width"].as_u64().unwrap() as u32 / 2);
    // Neurological puts it on the right half.
    let out_n = dir.path().join("ax_n.png");
    let report = json(&vbrain(&[
        "slice",
        &set,
        "--plane",
        "axial=4",
        "--window",
        "1,0.5",
        "--neurological",
        "--out",
        out_n.to_str().unwrap(),
        "--json",
    ]));
    let (x, y) = pixel(&report, 27.0, -6.0, false);
    assert!(x > report["width"].as_u64().unwrap() as u32 / 2);
    assert!(grey(&out_n, (x, y))[0] > 200);
}

#[test]
fn a_volume_that_misses_the_set_is_refused_and_the_set_still_slices() {
    let dir = tempfile::tempdir().unwrap();
    let set = set_with_mri(dir.path());
    // Move the volume 5 m away: its affine no longer meets the organs.
    let mri = Path::new(&set).join("mri.nii");
    let mut bytes = std::fs::read(&mri).unwrap();
    bytes[280 + 12..280 + 16].copy_from_slice(&5000f32.to_le_bytes());
    std::fs::write(&mri, bytes).unwrap();
    let out = dir.path().join("s.png");
    let run = vbrain(&["slice", &set, "--plane", "axial=4", "--out", out.to_str().unwrap(), "--json"]);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(stderr.contains("mri.nii") && stderr.contains("misses the set"), "{stderr}");
    let report = json(&run);
    assert_eq!(report["mri"], false);
    // Without its MRI the organs are filled in their colours: the block's pixel is not grey.
    let [r, g, b] = grey(&out, pixel(&report, 27.0, -6.0, true));
    assert!(r != g || g != b, "a filled organ, not grey: {r} {g} {b}");
}

#[test]
fn the_default_brain_slices_with_the_left_thalamus_on_the_right() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("c.png");
    let run = |extra: &[&str]| {
        json(&vbrain(
            &[
                &[
                    "slice",
                    &brain(),
                    "--plane",
                    "coronal=-15",
                    "--outlines",
                    "--out",
                    out.to_str().unwrap(),
                    "--json",
                    "--force",
                ][..],
                extra,
            ]
            .concat(),
        ))
    };
    let report = run(&[]);
    assert_eq!(report["mri"], true);
    let organs: Vec<&str> = report["organs"].as_array().unwrap().iter().map(|o| o.as_str().unwrap()).collect();
    for id in ["thalamus_l", "thalamus_r", "white_matter_l", "putamen_r", "hippocampus_l"] {
        assert!(organs.contains(&id), "{id} is cut at y = -15: {organs:?}");
    }
    assert!(!organs.contains(&"cerebellum_l") && !organs.contains(&"scalp"), "{organs:?}");
    // The left thalamus's middle (x about -11, z about 7) on the image's right half, inside
    // the brain's grey.
    let (x, y) = pixel(&report, -11.0, 7.0, true);
    assert!(x > 512, "{x}");
    assert!(grey(&out, (x, y))[0] > 60);
    let report = run(&["--neurological"]);
    assert!(pixel(&report, -11.0, 7.0, false).0 < 512);
}

#[test]
fn bad_slice_requests_are_refused_with_the_reason() {
    let dir = tempfile::tempdir().unwrap();
    let manifest = format!("{}/organset.json", brain());
    let out = dir.path().join("x.png");
    let o = out.to_str().unwrap();
    for (args, says) in [
        (vec!["slice", "--plane", "oblique=3", "--out", o], "not a plane"),
        (vec!["slice", "--plane", "axial=1e39", "--out", o], "out of range"),
        (vec!["slice", "--plane", "axial=0", "--size", "5000x5000", "--out", o], "at most"),
        (vec!["slice", "--plane", "axial=0", "--window", "0,0.5", "--out", o], "window"),
        (vec!["slice", "--plane", "axial=0", "--out", &manifest], "not a PNG"),
    ] {
        let run = vbrain(&args);
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert!(!run.status.success() && stderr.contains(says), "{args:?}: {stderr}");
    }
    assert!(!out.exists());
}

/// The viewer's slice panes: a click in the coronal pane moves the axial and sagittal panes, the
/// 3-D view's section planes and the selection there.
#[test]
fn a_click_in_the_coronal_pane_moves_the_other_panes_the_planes_and_the_selection() {
    use crate::viewer::{harness_of, organ};
    use eframe::egui;
    use egui_kittest::kittest::Queryable;
    use vbrain::mri::slice::Axis;
    use vbrain_ui::viewer::action::{Action, Window};
    use vbrain_ui::viewer::settings::ViewLayout;
    let mut h = harness_of(egui::Vec2::new(1000.0, 640.0));
    h.state_mut().settings_mut().view_layout = ViewLayout::ThreeDWithSlices;
    let ctx = h.ctx.clone();
    h.state_mut().perform(&ctx, vec![Action::Show(Window::Sections)]);
    h.run_steps(2);
    h.get_by_label("Axial").click();
    h.get_by_label("Sagittal").click();
    h.run_steps(3);
    assert_eq!(h.state().sections().current.planes.len(), 2);
    let (rect, pane) = h.state().slices().shown(Axis::Coronal).expect("the coronal pane is drawn");
    let y = pane.plane.at;
    // The left thalamus's middle on this coronal plane: x -11, z 7 (world millimetres).
    let target = glam::Vec3::new(-11.0, y, 7.0);
    let px = pane.pixel(target) / ctx.pixels_per_point();
    let at = rect.min + egui::vec2(px.x, px.y);
    assert!(rect.contains(at), "{at:?} in {rect:?}");
    crate::viewer::click(&h, at);
    h.run_steps(3);
    let point = h.state().slices().point.unwrap();
    assert!((point - target).length() < 1.5, "the crosshair moved to {point}, not {target}");
    let (_, axial) = h.state().slices().shown(Axis::Axial).unwrap();
    let (_, sagittal) = h.state().slices().shown(Axis::Sagittal).unwrap();
    assert!((axial.plane.at - 7.0).abs() < 1.5 && (sagittal.plane.at + 11.0).abs() < 1.5);
    let planes = &h.state().sections().planes;
    assert!((planes[0].mm - point.z).abs() < 0.01 && (planes[2].mm - point.x).abs() < 0.01, "{planes:?}");
    assert_eq!(h.state().selected(), Some(organ(&h, "thalamus_l")), "the organ under the click is selected");
    assert_eq!(h.state().slices().highlight, Some(organ(&h, "thalamus_l")), "and outlined in the panes");
    // The wheel over the axial pane steps its plane 1 mm.
    let (rect, _) = h.state().slices().shown(Axis::Axial).unwrap();
    h.event(egui::Event::PointerMoved(rect.center()));
    h.event(egui::Event::MouseWheel {
        unit: egui::MouseWheelUnit::Line,
        delta: egui::vec2(0.0, 1.0),
        phase: egui::TouchPhase::Move,
        source: egui::MouseWheelSource::Wheel,
        modifiers: egui::Modifiers::NONE,
    });
    h.run_steps(2);
    let moved = h.state().slices().point.unwrap();
    assert!((moved.z - point.z - 1.0).abs() < 0.01, "{moved} after {point}");
}

/// `vbrain quiz --mode mri`: each question on a slice that names its plane, its picture written.
#[test]
fn an_mri_worksheet_asks_on_slices() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("quiz");
    let o = out.to_str().unwrap();
    let v = json(&vbrain(&[
        "quiz",
        &brain(),
        "--mode",
        "mri",
        "--questions",
        "3",
        "--seed",
        "5",
        "--size",
        "320x320",
        "--out",
        o,
        "--json",
    ]));
    let questions = v["questions"].as_array().unwrap();
    assert_eq!(questions.len(), 3);
    for q in questions {
        assert!(["axial", "coronal", "sagittal"].contains(&q["slice"]["plane"].as_str().unwrap()), "{q}");
        assert!(Path::new(q["image"].as_str().unwrap()).is_file());
    }
    let md = std::fs::read_to_string(out.join("questions.md")).unwrap();
    assert_eq!(md.matches(" slice (").count(), 3, "{md}");
}

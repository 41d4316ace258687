//! animation.html holds the scene it claims (the data parsed back equals the scene's), works
//! offline (nothing fetched: no URL, no external script or style), and the strobe figure
//! shows the instants it claims.

use mechanism::output::{View, animation_html, plot_strobe, strobe_frames};

use crate::scene_support::{L, four_bar, four_bar_scene};
use crate::support::temp_dir;

/// The JSON inside `<script type="application/json" id="scene-data">`.
pub fn embedded_data(html: &str) -> serde_json::Value {
    let open = r#"<script type="application/json" id="scene-data">"#;
    let start = html.find(open).expect("data block") + open.len();
    let end = start + html[start..].find("</script>").expect("end of data block");
    serde_json::from_str(&html[start..end].replace("<\\/", "</")).expect("valid JSON")
}

#[test]
fn the_page_holds_the_trajectory_it_claims() {
    let scene = four_bar_scene(101);
    let html = animation_html(&scene).unwrap();
    let data = embedded_data(&html);
    let times: Vec<f64> = serde_json::from_value(data["times"].clone()).unwrap();
    let positions: Vec<f64> = serde_json::from_value(data["positions"].clone()).unwrap();
    assert_eq!(times, scene.times);
    assert_eq!(positions.len(), 101 * 4 * 3);
    // Every frame's points are the closed form at that frame's crank angle, bit for bit
    // (the JSON numbers are shortest round-trip representations).
    for (f, t) in times.iter().enumerate() {
        let expected = four_bar(std::f64::consts::PI / 2.0 + 2.0 * std::f64::consts::PI * t);
        for (i, p) in expected.iter().enumerate() {
            assert_eq!(&positions[3 * (4 * f + i)..3 * (4 * f + i) + 3], p);
        }
    }
    // The loop closes in the page's data: |B - A| = l2 and |B - D| = l3 at every frame.
    for f in 0..101 {
        let at = |i: usize| &positions[3 * (4 * f + i)..3 * (4 * f + i) + 3];
        let dist = |a: &[f64], b: &[f64]| ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt();
        assert!((dist(at(1), at(2)) - L[1]).abs() < 1e-12);
        assert!((dist(at(2), at(3)) - L[2]).abs() < 1e-12);
    }
    assert_eq!(data["points"][0]["ground"], true);
    assert_eq!(data["lines"], serde_json::json!([[0, 1], [1, 2], [2, 3]]));
}

#[test]
fn the_page_works_offline() {
    let html = animation_html(&four_bar_scene(11)).unwrap();
    for external in ["http://", "https://", "src=", "<link", "@import", "url("] {
        assert!(!html.contains(external), "the page refers to {external}");
    }
    assert!(html.contains("<canvas id=\"view\""));
}

#[test]
fn a_name_cannot_break_out_of_the_data_block() {
    let mut scene = four_bar_scene(3);
    scene.name = "</script><script>alert(1)</script>".into();
    let html = animation_html(&scene).unwrap();
    assert_eq!(
        html.matches("</script>").count(),
        2,
        "only the two real closing tags"
    );
    assert_eq!(embedded_data(&html)["name"], scene.name.as_str());
}

#[test]
fn the_strobe_shows_evenly_spaced_instants_from_first_to_last() {
    let scene = four_bar_scene(101);
    assert_eq!(strobe_frames(&scene, 5), vec![0, 25, 50, 75, 100]);
    assert_eq!(strobe_frames(&scene, 1), vec![100]);
    // A planar drawing in z = 0 is seen face on.
    let p = View::Auto.projection(&scene);
    assert_eq!((p.right, p.up), ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]));
    let dir = temp_dir("strobe");
    let files = plot_strobe(&dir.join("mechanism"), &scene, View::Auto, 12).unwrap();
    assert_eq!(files.len(), 2);
    let svg = std::fs::read_to_string(&files[1]).unwrap();
    assert!(svg.contains("12 instants"), "the title states the instants");
    assert!(std::fs::metadata(&files[0]).unwrap().len() > 10_000);
}

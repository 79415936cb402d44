//! Main-bearing loads act at each cylinder's own crank pin: a vee on split
//! pins loads its bearings by the vector sum of its pins' forces.

use enginedyn_engine::file::parse;

/// A 90° V-twin on one throw, each load a constant 1 N toward the crank
/// axis, no tangential force and no unbalance: the throw carries the sum of
/// two unit vectors along its pins, `2 cos(delta/2)` for pins `delta`
/// apart, and each of its two bearings half of it, `cos(delta/2)`, at every
/// angle. Shared pins (`delta = 0`) give 1 N; split 60° apart, cos 30°.
/// To 1e-12.
#[test]
fn bearing_loads_follow_each_pin() {
    for (crank, delta) in [("[0]", 0.0f64), ("[0, 60]", 60.0), ("[0, -90]", -90.0)] {
        let text = format!(
            "cycle = \"four-stroke\"\ncylinders = 2\nlayout = \"vee\"\nbank_angle_deg = 90\n\
             firing_order = [1, 2]\ncrank_angles_deg = {crank}\nbore_mm = 80\nstroke_mm = 80\n\
             lambda = 0.25\ncompression_ratio = 10\n[masses]\npiston_group_kg = 0.5\nrod_kg = 0.5\n"
        );
        let e = parse(&text, "v2").unwrap();
        assert_eq!(e.split_pins(), delta != 0.0);
        let n = 720;
        let step = (720.0f64 / n as f64).to_radians();
        let zero = vec![0.0; n];
        let one = vec![1.0; n];
        let loads = enginedyn_torque::main_bearing_loads(&e, step, |_| &zero, |_| &one, 0.0);
        assert_eq!(loads.len(), 2);
        let want = (delta.to_radians() / 2.0).cos();
        for bearing in &loads {
            for &v in bearing {
                assert!((v - want).abs() < 1e-12, "{crank}: {v} vs {want}");
            }
        }
    }
}

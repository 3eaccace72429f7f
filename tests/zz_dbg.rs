use strider::anim::bvh::{self, BvhOptions};
#[test]
fn zz() {
    for path in ["target/tmp/upper_body_scenes/shelves_2/episode_0.bvh", "/tmp/oldbvh/episode_0.bvh"] {
        let t = std::fs::read_to_string(path).unwrap();
        let f = bvh::parse(&t, "e", "e", &BvhOptions::default()).unwrap();
        let sk = &f.skeleton;
        let chest = sk.joints().iter().position(|j| j.name == "Chest").unwrap();
        let mut g = Vec::new();
        let mut prev = false;
        for (k, fr) in f.clip.frames.iter().enumerate() {
            sk.globals(fr, &mut g);
            let (root, q) = g[0];
            let qc = q.inverse() * g[chest].1;
            let twist = {
                let v = qc * glam::DVec3::X;
                v.y.atan2(v.x).to_degrees()
            };
            let mut s = String::new();
            let mut bad = false;
            for (i, j) in sk.joints().iter().enumerate() {
                if j.name.contains("Foot") {
                    let d = q.inverse() * (sk.tip(&g, i) - root);
                    if d.y.abs() > 0.3 {
                        bad = true;
                    }
                    s += &format!(" {} {:.2} {:.2} {:.2}", j.name, d.x, d.y, d.z + root.z);
                }
            }
            if bad && !prev {
                eprintln!("{path} {k}: twist {twist:.0} {s}");
            }
            prev = bad;
        }
    }
}

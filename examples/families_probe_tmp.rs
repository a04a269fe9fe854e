use wmslice::datasets::families::{all, answers::answers};
use wmslice::mesh::validate::validate;
fn main() {
    for f in all() {
        let mut faces = 0; let mut levels = 0; let mut kinds = std::collections::BTreeMap::new();
        let t = std::time::Instant::now();
        for seed in 0..20u64 {
            let m = f.generate(seed);
            let r = validate(&m);
            if !r.is_accepted() { println!("{} seed {seed}: REJECTED\n{r}", f.name); continue; }
            faces += m.num_faces();
            let a = answers(m, f.snap().as_ref()).unwrap();
            levels += a.levels.len();
            for l in &a.levels { *kinds.entry(format!("{:?}", l.kind)).or_insert(0) += 1; for &s in &l.summary.saddles { *kinds.entry(format!("m{s}")).or_insert(0)+=1; } }
        }
        println!("{}: faces {faces} levels {levels} {:?} {:?}", f.name, kinds, t.elapsed());
    }
}

use rtlang::render::{render, RenderOptions};
fn main() {
    let a: Vec<String> = std::env::args().collect();
    let loaded = match rtlang::lang::load_scene(std::path::Path::new(&a[1]), &[]) {
        Ok(l) => l,
        Err(e) => {
            for r in e {
                eprintln!("{r:?}");
            }
            return;
        }
    };
    let scene = loaded.scene;
    let world = rtlang::geometry::build::World::build(&scene).unwrap();
    let mut opts = RenderOptions::from_settings(&scene.settings);
    opts.width = a[3].parse().unwrap();
    opts.height =
        (opts.width as f32 * scene.settings.height as f32 / scene.settings.width as f32) as u32;
    opts.spp = a[4].parse().unwrap();
    let t = std::time::Instant::now();
    let out = render(&scene, &world, &opts, &|_| {}).unwrap();
    eprintln!("{:?} {:?}", t.elapsed(), out.stats);
    rtlang::render::output::write_image(
        std::path::Path::new(&a[2]),
        out.width,
        out.height,
        &out.pixels,
    )
    .unwrap();
}

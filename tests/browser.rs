//! Input: HTML viewers written by the library and by `wmslice demo`.
//! Output: checks in a real browser (Debian's `chromium`, headless): the
//! script runs and picks the layer and toggles from the URL fragment
//! (`--dump-dom`), and screenshots show the right colours where they
//! belong (pixels read with a small PNG decoder below).
//!
//! Without chromium these tests are skipped, unless the environment
//! variable `CI` is set: in CI a missing browser is a failure. The browser
//! is found as `$WMSLICE_CHROMIUM`, else `chromium`, `chromium-browser`,
//! `google-chrome` on `PATH`.
//!
//! `WMSLICE_UPDATE_DEMO_PNG=1` also writes the screenshot of every kind at
//! one level to `docs/demo.png` (the README's picture).

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};
use wmslice::exact::parse_rational;
use wmslice::output::html::{viewer, ViewerLayer, ViewerOptions};
use wmslice::output::svg::{colour, Scene};
use wmslice::{datasets, LevelSet, Mesh, Slicer};

// ---------------------------------------------------------------- browser

fn find_chromium() -> Option<PathBuf> {
    if let Some(p) = std::env::var_os("WMSLICE_CHROMIUM") {
        return Some(PathBuf::from(p));
    }
    let path = std::env::var_os("PATH")?;
    for dir in std::env::split_paths(&path) {
        for name in ["chromium", "chromium-browser", "google-chrome"] {
            let p = dir.join(name);
            if p.is_file() {
                return Some(p);
            }
        }
    }
    None
}

/// The browser, or `None` to skip (only outside CI).
fn chromium() -> Option<PathBuf> {
    match find_chromium() {
        Some(p) => Some(p),
        None if std::env::var_os("CI").is_some() => {
            panic!("CI is set but chromium is missing: apt-get install -y chromium")
        }
        None => {
            eprintln!("skipping: chromium not found (set CI to make this a failure)");
            None
        }
    }
}

/// Runs headless chromium on `url` with `extra` arguments; returns stdout.
fn run_chromium(bin: &Path, extra: &[String], url: &str) -> String {
    let profile = tempfile::tempdir().expect("temp profile");
    let mut child = Command::new(bin)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--hide-scrollbars",
            "--force-device-scale-factor=1",
        ])
        .arg(format!("--user-data-dir={}", profile.path().display()))
        .args(extra)
        .arg(url)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start chromium");
    let mut stdout = child.stdout.take().expect("stdout");
    let reader = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = stdout.read_to_string(&mut s);
        s
    });
    let mut stderr = child.stderr.take().expect("stderr");
    let err_reader = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = stderr.read_to_string(&mut s);
        s
    });
    let deadline = Instant::now() + Duration::from_secs(90);
    let status = loop {
        if let Some(s) = child.try_wait().expect("wait") {
            break s;
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            panic!("chromium did not finish within 90 s");
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    let out = reader.join().unwrap_or_default();
    let err = err_reader.join().unwrap_or_default();
    assert!(status.success(), "chromium failed: {status}\n{err}");
    out
}

fn url(file: &Path, fragment: &str) -> String {
    format!(
        "file://{}#{fragment}",
        file.canonicalize().unwrap().display()
    )
}

fn dump_dom(bin: &Path, file: &Path, fragment: &str) -> String {
    run_chromium(bin, &["--dump-dom".into()], &url(file, fragment))
}

fn screenshot(bin: &Path, file: &Path, fragment: &str, size: (u32, u32), png: &Path) -> Image {
    let _ = std::fs::remove_file(png);
    run_chromium(
        bin,
        &[
            format!("--screenshot={}", png.display()),
            format!("--window-size={},{}", size.0, size.1),
        ],
        &url(file, fragment),
    );
    decode_png(&std::fs::read(png).expect("screenshot written")).expect("decodable PNG")
}

/// The value of `name="..."` on `<body>` in a dumped DOM.
fn body_attr(dom: &str, name: &str) -> Option<String> {
    let body = &dom[dom.find("<body")?..];
    let body = &body[..body.find('>')?];
    let key = format!("{name}=\"");
    let start = body.find(&key)? + key.len();
    Some(body[start..start + body[start..].find('"')?].to_string())
}

/// The drawing's rectangle `[x, y, w, h]` in a screenshot of `size`, from
/// the viewer's fixed layout (`output::html`: left 8, top 92, 276 px kept
/// free on the right and 8 below). `--dump-dom` runs with a smaller
/// viewport than `--screenshot`, so the page's own report
/// (`data-view-rect`) is only checked for its corner.
fn view_rect(size: (u32, u32)) -> [usize; 4] {
    [8, 92, size.0 as usize - 284, size.1 as usize - 100]
}

fn check_view_corner(dom: &str) {
    let r = body_attr(dom, "data-view-rect").expect("data-view-rect");
    assert!(r.starts_with("8,92,"), "the drawing's corner moved: {r}");
}

fn text_of(dom: &str, id: &str) -> String {
    let key = format!("id=\"{id}\"");
    let at = dom.find(&key).unwrap_or_else(|| panic!("#{id} in the DOM"));
    let rest = &dom[at..];
    let rest = &rest[rest.find('>').unwrap() + 1..];
    rest[..rest.find('<').unwrap()].to_string()
}

// ------------------------------------------------------------------ pixels

type Rgb = [u8; 3];

fn rgb(hex: &str) -> Rgb {
    let v = |i: usize| u8::from_str_radix(&hex[i..i + 2], 16).unwrap();
    [v(1), v(3), v(5)]
}

fn near(a: Rgb, b: Rgb) -> bool {
    a.iter().zip(&b).all(|(x, y)| x.abs_diff(*y) <= 3)
}

struct Image {
    width: usize,
    height: usize,
    px: Vec<Rgb>,
}

impl Image {
    fn at(&self, x: usize, y: usize) -> Rgb {
        self.px[y * self.width + x]
    }

    /// Pixels of colour `c` inside the rectangle `[x, y, w, h]`.
    fn count(&self, r: [usize; 4], c: Rgb) -> usize {
        let mut n = 0;
        for y in r[1]..(r[1] + r[3]).min(self.height) {
            for x in r[0]..(r[0] + r[2]).min(self.width) {
                if near(self.at(x, y), c) {
                    n += 1;
                }
            }
        }
        n
    }
}

/// A minimal inflate (RFC 1951) for the screenshots: stored, fixed and
/// dynamic Huffman blocks. Errors instead of panics on bad data.
mod inflate {
    pub struct Bits<'a> {
        data: &'a [u8],
        pos: usize,
        buf: u64,
        n: u32,
    }

    impl Bits<'_> {
        pub fn bits(&mut self, k: u32) -> Result<u32, String> {
            while self.n < k {
                let b = *self.data.get(self.pos).ok_or("inflate: out of data")?;
                self.buf |= u64::from(b) << self.n;
                self.pos += 1;
                self.n += 8;
            }
            let v = (self.buf & ((1u64 << k) - 1)) as u32;
            self.buf >>= k;
            self.n -= k;
            Ok(v)
        }

        fn align(&mut self) {
            let r = self.n % 8;
            self.buf >>= r;
            self.n -= r;
        }
    }

    struct Huff {
        count: [i32; 16],
        symbol: Vec<u16>,
    }

    fn huff(lengths: &[u8]) -> Huff {
        let mut count = [0i32; 16];
        for &l in lengths {
            count[l as usize] += 1;
        }
        count[0] = 0;
        let mut offs = [0i32; 16];
        for len in 1..15 {
            offs[len + 1] = offs[len] + count[len];
        }
        let mut symbol = vec![0u16; lengths.len()];
        for (s, &l) in lengths.iter().enumerate() {
            if l != 0 {
                symbol[offs[l as usize] as usize] = s as u16;
                offs[l as usize] += 1;
            }
        }
        Huff { count, symbol }
    }

    fn decode(b: &mut Bits, h: &Huff) -> Result<usize, String> {
        let (mut code, mut first, mut index) = (0i32, 0i32, 0i32);
        for len in 1..16 {
            code |= b.bits(1)? as i32;
            let count = h.count[len];
            if code - count < first {
                return Ok(h.symbol[(index + code - first) as usize] as usize);
            }
            index += count;
            first = (first + count) << 1;
            code <<= 1;
        }
        Err("inflate: bad code".into())
    }

    const LBASE: [usize; 29] = [
        3, 4, 5, 6, 7, 8, 9, 10, 11, 13, 15, 17, 19, 23, 27, 31, 35, 43, 51, 59, 67, 83, 99, 115,
        131, 163, 195, 227, 258,
    ];
    const LEXT: [u32; 29] = [
        0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2, 3, 3, 3, 3, 4, 4, 4, 4, 5, 5, 5, 5, 0,
    ];
    const DBASE: [usize; 30] = [
        1, 2, 3, 4, 5, 7, 9, 13, 17, 25, 33, 49, 65, 97, 129, 193, 257, 385, 513, 769, 1025, 1537,
        2049, 3073, 4097, 6145, 8193, 12289, 16385, 24577,
    ];
    const DEXT: [u32; 30] = [
        0, 0, 0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6, 6, 7, 7, 8, 8, 9, 9, 10, 10, 11, 11, 12, 12,
        13, 13,
    ];
    const ORDER: [usize; 19] = [
        16, 17, 18, 0, 8, 7, 9, 6, 10, 5, 11, 4, 12, 3, 13, 2, 14, 1, 15,
    ];

    fn codes(b: &mut Bits, out: &mut Vec<u8>, lit: &Huff, dist: &Huff) -> Result<(), String> {
        loop {
            let sym = decode(b, lit)?;
            if sym < 256 {
                out.push(sym as u8);
            } else if sym == 256 {
                return Ok(());
            } else {
                let s = sym - 257;
                if s >= 29 {
                    return Err("inflate: bad length".into());
                }
                let len = LBASE[s] + b.bits(LEXT[s])? as usize;
                let ds = decode(b, dist)?;
                if ds >= 30 {
                    return Err("inflate: bad distance".into());
                }
                let d = DBASE[ds] + b.bits(DEXT[ds])? as usize;
                if d > out.len() {
                    return Err("inflate: distance too far".into());
                }
                for _ in 0..len {
                    out.push(out[out.len() - d]);
                }
            }
        }
    }

    /// Inflates a raw deflate stream.
    pub fn inflate(data: &[u8]) -> Result<Vec<u8>, String> {
        let mut b = Bits {
            data,
            pos: 0,
            buf: 0,
            n: 0,
        };
        let mut out = Vec::new();
        loop {
            let last = b.bits(1)?;
            match b.bits(2)? {
                0 => {
                    b.align();
                    let len = b.bits(16)?;
                    let nlen = b.bits(16)?;
                    if len != !nlen & 0xffff {
                        return Err("inflate: bad stored block".into());
                    }
                    for _ in 0..len {
                        out.push(b.bits(8)? as u8);
                    }
                }
                1 => {
                    let mut l = [0u8; 288];
                    l[..144].fill(8);
                    l[144..256].fill(9);
                    l[256..280].fill(7);
                    l[280..].fill(8);
                    codes(&mut b, &mut out, &huff(&l), &huff(&[5u8; 30]))?;
                }
                2 => {
                    let nlen = b.bits(5)? as usize + 257;
                    let ndist = b.bits(5)? as usize + 1;
                    let ncode = b.bits(4)? as usize + 4;
                    let mut cl = [0u8; 19];
                    for &i in ORDER.iter().take(ncode) {
                        cl[i] = b.bits(3)? as u8;
                    }
                    let lencode = huff(&cl);
                    let mut lens = vec![0u8; nlen + ndist];
                    let mut i = 0;
                    while i < nlen + ndist {
                        let sym = decode(&mut b, &lencode)?;
                        if sym < 16 {
                            lens[i] = sym as u8;
                            i += 1;
                            continue;
                        }
                        let (val, rep) = match sym {
                            16 if i > 0 => (lens[i - 1], 3 + b.bits(2)? as usize),
                            16 => return Err("inflate: repeat with no length".into()),
                            17 => (0, 3 + b.bits(3)? as usize),
                            _ => (0, 11 + b.bits(7)? as usize),
                        };
                        if i + rep > lens.len() {
                            return Err("inflate: too many lengths".into());
                        }
                        lens[i..i + rep].fill(val);
                        i += rep;
                    }
                    codes(&mut b, &mut out, &huff(&lens[..nlen]), &huff(&lens[nlen..]))?;
                }
                _ => return Err("inflate: bad block type".into()),
            }
            if last == 1 {
                return Ok(out);
            }
        }
    }
}

/// Decodes an 8-bit RGB or RGBA, non-interlaced PNG (what Chromium writes).
fn decode_png(bytes: &[u8]) -> Result<Image, String> {
    if !bytes.starts_with(b"\x89PNG\r\n\x1a\n") {
        return Err("not a PNG".into());
    }
    let mut pos = 8;
    let (mut w, mut h, mut bpp) = (0usize, 0usize, 0usize);
    let mut idat = Vec::new();
    while pos + 8 <= bytes.len() {
        let len = u32::from_be_bytes(bytes[pos..pos + 4].try_into().unwrap()) as usize;
        let kind = &bytes[pos + 4..pos + 8];
        let data = bytes
            .get(pos + 8..pos + 8 + len)
            .ok_or("PNG: truncated chunk")?;
        match kind {
            b"IHDR" => {
                w = u32::from_be_bytes(data[0..4].try_into().unwrap()) as usize;
                h = u32::from_be_bytes(data[4..8].try_into().unwrap()) as usize;
                if data[8] != 8 || data[12] != 0 {
                    return Err("PNG: only 8-bit, non-interlaced".into());
                }
                bpp = match data[9] {
                    2 => 3,
                    6 => 4,
                    c => return Err(format!("PNG: colour type {c}")),
                };
            }
            b"IDAT" => idat.extend_from_slice(data),
            b"IEND" => break,
            _ => {}
        }
        pos += 12 + len;
    }
    let raw = inflate::inflate(idat.get(2..).ok_or("PNG: no data")?)?;
    let stride = w * bpp;
    if raw.len() < h * (stride + 1) {
        return Err("PNG: short image data".into());
    }
    let mut prev = vec![0u8; stride];
    let mut px = Vec::with_capacity(w * h);
    for y in 0..h {
        let filter = raw[y * (stride + 1)];
        let mut line = raw[y * (stride + 1) + 1..(y + 1) * (stride + 1)].to_vec();
        for i in 0..stride {
            let a = if i >= bpp { line[i - bpp] } else { 0 };
            let b = prev[i];
            let c = if i >= bpp { prev[i - bpp] } else { 0 };
            let add = match filter {
                0 => 0,
                1 => a,
                2 => b,
                3 => ((u16::from(a) + u16::from(b)) / 2) as u8,
                4 => {
                    let p = i16::from(a) + i16::from(b) - i16::from(c);
                    let (pa, pb, pc) = (
                        (p - i16::from(a)).abs(),
                        (p - i16::from(b)).abs(),
                        (p - i16::from(c)).abs(),
                    );
                    if pa <= pb && pa <= pc {
                        a
                    } else if pb <= pc {
                        b
                    } else {
                        c
                    }
                }
                f => return Err(format!("PNG: filter {f}")),
            };
            line[i] = line[i].wrapping_add(add);
        }
        for x in 0..w {
            px.push([line[x * bpp], line[x * bpp + 1], line[x * bpp + 2]]);
        }
        prev = line;
    }
    Ok(Image {
        width: w,
        height: h,
        px,
    })
}

// ------------------------------------------------------------------ scenes

fn slice(mesh: &Mesh, z: &str) -> LevelSet {
    Slicer::new(mesh)
        .expect("valid mesh")
        .slice_at(&parse_rational(z).unwrap())
        .expect("slice")
}

fn write_viewer(dir: &Path, name: &str, mesh: &Mesh, layers: &[(&str, &LevelSet)]) -> PathBuf {
    let scene = Scene::new(mesh, None);
    let layers: Vec<ViewerLayer> = layers
        .iter()
        .map(|(note, ls)| ViewerLayer {
            heading: name.to_string(),
            note: (*note).to_string(),
            level: ls,
            scene: &scene,
        })
        .collect();
    let page = viewer(
        &layers,
        &ViewerOptions {
            title: format!("wmslice: {name}"),
            arrows: false,
            ..Default::default()
        },
    );
    let path = dir.join(format!("{name}.html"));
    std::fs::write(&path, page).unwrap();
    path
}

/// Built-in datasets side by side in one mesh, shifted so that z = 2 shows
/// every kind: a ridge ring and a valley ring (lying tori at half size), a
/// monkey saddle with one outer loop and three holes (double torus), F up
/// and F down (two cylinders), nine minima (grid) and four maxima
/// (saddle8). Shifts and halving are exact in binary.
fn every_kind_mesh() -> Mesh {
    let rows: [&[(&str, f64, f64)]; 2] = [
        &[
            ("lying_torus", 0.5, 0.0),
            ("lying_torus", 0.5, 3.0),
            ("double_torus", 1.0, 0.0),
        ],
        &[
            ("cylinder", 1.0, 0.0),
            ("cylinder", 1.0, 2.0),
            ("grid", 1.0, 1.0),
            ("saddle8", 1.0, -1.0),
        ],
    ];
    let mut out = Mesh::default();
    let mut y_top = 0.0f64;
    for row in rows {
        let mut x = 0.0f64;
        let mut row_h = 0.0f64;
        for &(name, scale, dz) in row {
            let m = datasets::by_name(name).unwrap().build();
            let bmin = |k: usize| m.positions.iter().map(|p| p[k]).fold(f64::MAX, f64::min);
            let bmax = |k: usize| m.positions.iter().map(|p| p[k]).fold(f64::MIN, f64::max);
            let (x0, y1) = (bmin(0) * scale, bmax(1) * scale);
            let w = (bmax(0) - bmin(0)) * scale;
            row_h = row_h.max((bmax(1) - bmin(1)) * scale);
            let base = out.positions.len() as u32;
            for p in &m.positions {
                out.positions
                    .push([p[0] * scale - x0 + x, p[1] * scale - y1 + y_top, p[2] + dz]);
            }
            for f in &m.faces {
                out.faces.push(f.map(|v| wmslice::VertexId(v.0 + base)));
            }
            x += w + 1.0;
        }
        y_top -= row_h + 1.0;
    }
    out
}

fn temp_dir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("wmslice-browser-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

// ------------------------------------------------------------------- tests

#[test]
fn png_decoder_reads_a_stored_block_image() {
    // A 2x1 RGB image, filter 1 (sub), zlib with one stored block.
    let raw = [1u8, 10, 20, 30, 5, 5, 5];
    let mut z = vec![
        0x78,
        0x01,
        0x01,
        raw.len() as u8,
        0,
        !(raw.len() as u8),
        0xff,
    ];
    z.extend_from_slice(&raw);
    z.extend_from_slice(&[0, 0, 0, 0]);
    let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
    let chunk = |png: &mut Vec<u8>, kind: &[u8], data: &[u8]| {
        png.extend_from_slice(&(data.len() as u32).to_be_bytes());
        png.extend_from_slice(kind);
        png.extend_from_slice(data);
        png.extend_from_slice(&[0, 0, 0, 0]);
    };
    chunk(&mut png, b"IHDR", &[0, 0, 0, 2, 0, 0, 0, 1, 8, 2, 0, 0, 0]);
    chunk(&mut png, b"IDAT", &z);
    chunk(&mut png, b"IEND", &[]);
    let img = decode_png(&png).unwrap();
    assert_eq!(img.px, [[10, 20, 30], [15, 25, 35]]);
}

#[test]
fn cylinder_top_shows_the_f_colour_inside_the_rim_and_no_contour_stroke() {
    let Some(bin) = chromium() else { return };
    let dir = temp_dir("cylinder");
    let mesh = datasets::by_name("cylinder").unwrap().build();
    let (mid, top) = (slice(&mesh, "1"), slice(&mesh, "2"));
    let page = write_viewer(
        &dir,
        "cylinder",
        &mesh,
        &[("regular", &mid), ("top cap", &top)],
    );

    let dom = dump_dom(&bin, &page, "layer=1");
    assert_eq!(
        body_attr(&dom, "data-ready").as_deref(),
        Some("1"),
        "the script ran"
    );
    assert_eq!(body_attr(&dom, "data-layer").as_deref(), Some("1"));
    assert_eq!(text_of(&dom, "level"), "2");
    assert!(dom.contains("1 / 0 / 0"), "F up / down / flat counts shown");
    check_view_corner(&dom);
    let rect = view_rect((800, 800));
    let centre = (rect[0] + rect[2] / 2, rect[1] + rect[3] / 2);

    let img = screenshot(&bin, &page, "layer=1", (800, 800), &dir.join("top.png"));
    assert_eq!((img.width, img.height), (800, 800));
    let f_up = rgb(colour::F_UP);
    assert!(
        near(img.at(centre.0, centre.1), f_up),
        "centre is {:?}",
        img.at(centre.0, centre.1)
    );
    assert!(img.count(rect, f_up) > 20_000, "a filled disk of F colour");
    assert_eq!(
        img.count(rect, rgb(colour::SO_OUTER)),
        0,
        "no contour stroke"
    );
    assert_eq!(img.count(rect, rgb(colour::SO_FILL)), 0, "no contour fill");
    assert!(img.count(rect, rgb(colour::DF)) > 50, "the dF outline");

    // Control: the regular level does show the contour stroke and fill.
    let img = screenshot(&bin, &page, "layer=0", (800, 800), &dir.join("mid.png"));
    assert!(img.count(rect, rgb(colour::SO_OUTER)) > 200);
    assert!(near(img.at(centre.0, centre.1), rgb(colour::SO_FILL)));
    assert_eq!(img.count(rect, f_up), 0);

    // A toggle from the fragment hides F.
    let img = screenshot(&bin, &page, "layer=1&f=0", (800, 800), &dir.join("nof.png"));
    assert_eq!(img.at(centre.0, centre.1), [255, 255, 255]);
    assert_eq!(img.count(rect, f_up), 0);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_cylinder_far_out_or_scaled_to_1e_minus_300_is_drawn_as_at_home() {
    use wmslice::datasets::cross_check::{far_offset, scaled};
    use wmslice::exact::rational::{rat_from_f64, rat_to_string};
    let Some(bin) = chromium() else { return };
    let dir = temp_dir("frame");
    let mesh = datasets::by_name("cylinder").unwrap().build();
    let (t, far) = far_offset(&mesh).expect("a far offset");
    assert!(t >= 2f64.powi(40), "{t}");
    let tiny = scaled(&mesh, -1000).expect("exact scale");
    let size = (800, 800);
    let rect = view_rect(size);
    let fill = rgb(colour::SO_FILL);
    let mut counts = Vec::new();
    for (name, m, z) in [
        ("home", &mesh, parse_rational("1").unwrap()),
        ("far", &far, parse_rational("1").unwrap() + rat_from_f64(t)),
        (
            "tiny",
            &tiny,
            parse_rational("1").unwrap() / wmslice::exact::Rat::from_integer(2.into()).pow(1000),
        ),
    ] {
        let ls = slice(m, &rat_to_string(&z));
        let page = write_viewer(&dir, name, m, &[("regular", &ls)]);
        let img = screenshot(
            &bin,
            &page,
            "layer=0",
            size,
            &dir.join(format!("{name}.png")),
        );
        if name == "tiny" {
            // Its area, 2^-2000 times the disk's, runs to hundreds of
            // digits: the table shows the nearest double, the exact value
            // on hover.
            let area = wmslice::levelset::total_area(&ls.contours);
            let exact = rat_to_string(&area);
            assert!(exact.len() > 500);
            let dom = dump_dom(&bin, &page, "layer=0");
            let cell = format!(
                "<span title=\"{exact}\">~{}</span>",
                wmslice::exact::rational::rat_to_f64(&area)
            );
            assert!(dom.contains(&cell), "{cell} in the table");
            // The level, 2^-1000, has 300 digits: the heading shows its
            // nearest double, the exact level on hover.
            assert_eq!(text_of(&dom, "level"), format!("~{:e}", 2f64.powi(-1000)));
            assert!(dom.contains(&format!("title=\"{}\"", rat_to_string(&z))));
        }
        counts.push((
            img.count(rect, fill),
            img.count(rect, rgb(colour::SO_OUTER)),
        ));
    }
    // At home the disk fills the drawing; moved to 2^50 (32-bit floats
    // 2^26 apart) or scaled to 2^-1000 (below their range) it used to draw
    // nothing. Now each is the same disk, pixel for pixel up to
    // anti-aliasing.
    let (home_fill, home_rim) = counts[0];
    assert!(home_fill > 20_000 && home_rim > 200, "{counts:?}");
    for &(f, r) in &counts[1..] {
        assert!(f.abs_diff(home_fill) * 100 <= home_fill, "{counts:?}");
        assert!(r.abs_diff(home_rim) * 10 <= home_rim, "{counts:?}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn fragment_picks_a_layer_by_exact_level_and_sets_toggles() {
    let Some(bin) = chromium() else { return };
    let dir = temp_dir("fragment");
    let mesh = datasets::by_name("peg_cube").unwrap().build();
    let sets: Vec<LevelSet> = ["1", "3", "7/2", "4"]
        .iter()
        .map(|z| slice(&mesh, z))
        .collect();
    let layers: Vec<(&str, &LevelSet)> = sets.iter().map(|s| ("", s)).collect();
    let page = write_viewer(&dir, "peg_cube", &mesh, &layers);
    let dom = dump_dom(&bin, &page, "z=7/2&sno=0&lplus=off&arrows=1");
    assert_eq!(body_attr(&dom, "data-layer").as_deref(), Some("2"));
    assert_eq!(text_of(&dom, "level"), "7/2");
    let classes = body_attr(&dom, "class").unwrap_or_default();
    for c in ["hide-sno", "hide-lplus", "arrows"] {
        assert!(classes.split(' ').any(|x| x == c), "{c} in {classes}");
    }
    assert!(!classes.contains("hide-so"), "{classes}");
    // Out-of-range layers are clamped.
    let dom = dump_dom(&bin, &page, "layer=99");
    assert_eq!(body_attr(&dom, "data-layer").as_deref(), Some("3"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn every_kind_at_one_level_is_visible_in_the_viewer() {
    let mesh = every_kind_mesh();
    let ls = slice(&mesh, "2");
    // The scene really holds every kind.
    assert!(ls
        .contours
        .iter()
        .any(|l| l.role == wmslice::nest::Role::Hole));
    assert_eq!(ls.saddles.len(), 1);
    assert_eq!(ls.extrema.len(), 13);
    assert_eq!(ls.ridges.len(), 2);
    assert_eq!(ls.regions.len(), 2);
    let Some(bin) = chromium() else { return };
    let dir = temp_dir("every");
    let page = write_viewer(
        &dir,
        "every kind at z = 2",
        &mesh,
        &[(
            "ridge and valley rings, monkey saddle, F up and down, minima, maxima",
            &ls,
        )],
    );
    let size = (720, 440);
    let rect = view_rect(size);
    let png = dir.join("demo.png");
    let img = screenshot(&bin, &page, "layer=0&arrows=1", size, &png);
    for (what, c) in [
        ("S_O outer", colour::SO_OUTER),
        ("S_O hole", colour::SO_HOLE),
        ("F up", colour::F_UP),
        ("F down", colour::F_DOWN),
        ("dF", colour::DF),
        ("ridge", colour::RIDGE),
        ("valley", colour::VALLEY),
        ("P min", colour::P_MIN),
        ("P max", colour::P_MAX),
        ("saddle", colour::SADDLE),
        ("L-", colour::L_MINUS),
        ("L+", colour::L_PLUS),
    ] {
        let n = img.count(rect, rgb(c));
        assert!(n >= 10, "{what} ({c}) visible: {n} pixels");
    }
    if std::env::var_os("WMSLICE_UPDATE_DEMO_PNG").is_some() {
        let dst = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("docs")
            .join("demo.png");
        let bytes = std::fs::read(&png).unwrap();
        wmslice::output::atomic::write_atomic(&dst, &bytes).unwrap();
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn committed_demo_picture_is_a_small_png() {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("docs")
        .join("demo.png");
    let bytes = std::fs::read(&p).expect("docs/demo.png (WMSLICE_UPDATE_DEMO_PNG=1 writes it)");
    assert!(bytes.len() < 60_000, "{} bytes", bytes.len());
    let img = decode_png(&bytes).expect("a PNG");
    assert!(img.width >= 600 && img.height >= 400);
}

#[test]
fn demo_command_writes_a_working_viewer() {
    let dir = temp_dir("demo");
    let out = dir.join("sub").join("demo.html");
    let o = Command::new(env!("CARGO_BIN_EXE_wmslice"))
        .args(["demo", "-o", out.to_str().unwrap()])
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(stdout.contains("== double_torus at z = 2"), "{stdout}");
    assert!(stdout.contains("naive slicer"), "{stdout}");
    assert!(
        stdout.contains(&format!("to {}", out.display())),
        "{stdout}"
    );
    let page = std::fs::read_to_string(&out).unwrap();
    for h in ["double_torus", "lying_torus", "cylinder", "internal_torus"] {
        assert!(page.contains(&format!("\"heading\":\"{h}\"")), "{h}");
    }
    let Some(bin) = chromium() else { return };
    let dom = dump_dom(&bin, &out, "layer=3");
    assert_eq!(body_attr(&dom, "data-ready").as_deref(), Some("1"));
    assert_eq!(text_of(&dom, "heading"), "lying_torus");
    assert_eq!(text_of(&dom, "level"), "2");
    assert!(dom.contains("class=\"sno ridge\""), "the ridge is drawn");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `slice --format html` lists the mesh's critical heights beside the
/// slider: the upright torus has four (-3, -1, 1, 3; by hand in
/// `tests/critical.rs`); sliced at -2, -1 and 0, the layer at -1 is the
/// only one linked, and marked while it is shown.
#[test]
fn the_slice_viewer_lists_the_critical_heights() {
    let dir = temp_dir("critical");
    let out = dir.join("torus.html");
    let o = Command::new(env!("CARGO_BIN_EXE_wmslice"))
        .args([
            "slice",
            "upright_torus",
            "--at",
            "-2",
            "--at",
            "-1",
            "--at",
            "0",
        ])
        .args(["--format", "html", "-o", out.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let page = std::fs::read_to_string(&out).unwrap();
    assert!(
        page.contains(r#""critical":[{"z":"-3""#),
        "the list is in the page's data"
    );
    let Some(bin) = chromium() else { return };
    let dom = dump_dom(&bin, &out, "z=-1");
    assert_eq!(body_attr(&dom, "data-ready").as_deref(), Some("1"));
    // The list as the script built it (the script's source also holds
    // these tags).
    let list = |dom: &str| {
        let at = dom.find(r#"<div id="critical">"#).expect("the list");
        dom[at..at + dom[at..].find("</div>").unwrap()].to_string()
    };
    let shown = list(&dom);
    assert_eq!(shown.matches("<li data-z=").count(), 4, "{shown}");
    assert_eq!(
        shown.matches("<a data-to=").count(),
        1,
        "only -1 is a layer"
    );
    assert!(
        shown.contains(r#"<li data-z="-1" class="here">"#),
        "{shown}"
    );
    let dom = dump_dom(&bin, &out, "z=0");
    assert!(!list(&dom).contains("class=\"here\""), "0 is not critical");
    let _ = std::fs::remove_dir_all(&dir);
}

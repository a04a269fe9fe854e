//! Input: exact level sets (of one mesh or several) with their scenes.
//! Output: ONE self-contained HTML layer viewer: no network, no external
//! script, style sheet or font.
//!
//! The page embeds a JSON document (`<script type="application/json"
//! id="data">`) with, per layer, its heading, the exact level `"p/q"`, the
//! counts of each kind, and the layer's drawing from [`super::svg`] (same
//! classes and colours as the SVG files). A small inline script shows one
//! layer at a time in an inline `<svg>`:
//!
//! - a slider, buttons, and the keys Left/Right (also Up/Down, PageUp/
//!   PageDown by 10, Home/End) step through the layers;
//! - checkboxes toggle S_O, F (with dF), S_NO, P, saddles, L-, L+ and the
//!   direction arrows;
//! - the URL fragment holds the state and is read at load, so a link (or
//!   a test) picks the layer and the toggles:
//!   `#layer=3&so=1&f=1&sno=0&p=1&saddle=1&lminus=0&lplus=0&arrows=1`
//!   (`layer` is the 0-based index; `z=7/2` picks a layer by exact level;
//!   omitted toggles keep their defaults: all on, arrows as written).
//!
//! For scripted checks the script marks `<body>` with `data-layer` (the
//! layer shown), `data-ready="1"`, and the drawing's page rectangle as
//! `data-view-rect="x,y,width,height"` in CSS pixels; the drawing's
//! `data-frame` says where model coordinates went ([`super::svg::Frame`]).
//! The drawing area is placed by fixed CSS: left 8 px, top 92 px, up to
//! 276 px from the right edge and 8 px from the bottom.

use super::critical::holds;
use super::svg::{drawing, style, xml_escape, Scene, SvgOptions};
use crate::classify::{ExtremumKind, Facing, RidgeKind};
use crate::critical::CriticalReport;
use crate::exact::rational::{rat_to_f64, rat_to_string};
use crate::levelset::{total_area, LevelSet, Loop};
use crate::nest::Role;
use serde::Serialize;

/// One layer of the viewer.
pub struct ViewerLayer<'a> {
    /// What is sliced (a file or dataset name), shown above the drawing.
    pub heading: String,
    /// A short note on this level (may be empty).
    pub note: String,
    /// The level set.
    pub level: &'a LevelSet,
    /// The mesh it slices.
    pub scene: &'a Scene<'a>,
}

/// Viewer options.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ViewerOptions {
    /// The page title.
    pub title: String,
    /// Direction arrows shown at load (they can be toggled either way).
    pub arrows: bool,
    /// The mesh's critical heights, listed beside the slider (empty: no
    /// list). See [`critical_marks`].
    pub critical: Vec<CriticalMark>,
    /// Critical heights beyond the list (said under it).
    pub unlisted_marks: usize,
}

/// One critical height as the viewer lists it.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize)]
pub struct CriticalMark {
    /// The exact height, `"p/q"` (a layer at exactly this level is linked).
    pub z: String,
    /// The nearest double, for reading.
    pub approx: String,
    /// What its level set holds, in words.
    pub holds: String,
}

/// At most this many critical heights are listed in a page.
pub const MAX_MARKS: usize = 1000;

/// The viewer's list of the critical heights of `report` (the first
/// [`MAX_MARKS`]), and how many are left out.
pub fn critical_marks(report: &CriticalReport) -> (Vec<CriticalMark>, usize) {
    let marks: Vec<CriticalMark> = report
        .levels
        .iter()
        .take(MAX_MARKS)
        .map(|l| CriticalMark {
            z: rat_to_string(&l.z),
            approx: rat_to_f64(&l.z).to_string(),
            holds: holds(l),
        })
        .collect();
    let unlisted = report.levels.len() - marks.len();
    (marks, unlisted)
}

/// The counts of each kind at one level, as the viewer lists them.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize)]
pub struct Counts {
    /// S_O outer loops.
    pub so_outer: usize,
    /// S_O holes.
    pub so_hole: usize,
    /// Exact signed area of S_O, `"p/q"`.
    pub so_area: String,
    /// Its nearest double, for reading when the exact text is long.
    pub so_area_approx: String,
    /// F regions facing up.
    pub f_up: usize,
    /// F regions facing down.
    pub f_down: usize,
    /// Flat F regions.
    pub f_flat: usize,
    /// dF loops over all regions.
    pub df: usize,
    /// Open ridges.
    pub ridge_open: usize,
    /// Closed ridges.
    pub ridge_closed: usize,
    /// Open valleys.
    pub valley_open: usize,
    /// Closed valleys.
    pub valley_closed: usize,
    /// P minima.
    pub p_min: usize,
    /// P maxima.
    pub p_max: usize,
    /// `m` of each saddle.
    pub saddles: Vec<u32>,
    /// L- outer loops.
    pub lminus_outer: usize,
    /// L- holes.
    pub lminus_hole: usize,
    /// Exact signed area of L-, `"p/q"`.
    pub lminus_area: String,
    /// Its nearest double, for reading when the exact text is long.
    pub lminus_area_approx: String,
    /// L+ outer loops.
    pub lplus_outer: usize,
    /// L+ holes.
    pub lplus_hole: usize,
    /// Exact signed area of L+, `"p/q"`.
    pub lplus_area: String,
    /// Its nearest double, for reading when the exact text is long.
    pub lplus_area_approx: String,
}

/// Outer loops, holes, the exact total area and its nearest double.
fn roles(loops: &[Loop]) -> (usize, usize, String, String) {
    let outer = loops.iter().filter(|l| l.role == Role::Outer).count();
    let area = total_area(loops);
    let approx = rat_to_f64(&area).to_string();
    (outer, loops.len() - outer, rat_to_string(&area), approx)
}

impl Counts {
    /// The counts of a level set.
    pub fn of(ls: &LevelSet) -> Self {
        let (so_outer, so_hole, so_area, so_area_approx) = roles(&ls.contours);
        let (lminus_outer, lminus_hole, lminus_area, lminus_area_approx) = roles(&ls.below);
        let (lplus_outer, lplus_hole, lplus_area, lplus_area_approx) = roles(&ls.above);
        let facing = |f: Facing| ls.regions.iter().filter(|r| r.facing == f).count();
        let ridges = |k: RidgeKind, closed: bool| {
            ls.ridges
                .iter()
                .filter(|r| r.kind == k && r.closed == closed)
                .count()
        };
        let points = |k: ExtremumKind| ls.extrema.iter().filter(|p| p.kind == k).count();
        Counts {
            so_outer,
            so_hole,
            so_area,
            so_area_approx,
            f_up: facing(Facing::Up),
            f_down: facing(Facing::Down),
            f_flat: facing(Facing::Flat),
            df: ls.regions.iter().map(|r| r.boundary.len()).sum(),
            ridge_open: ridges(RidgeKind::Ridge, false),
            ridge_closed: ridges(RidgeKind::Ridge, true),
            valley_open: ridges(RidgeKind::Valley, false),
            valley_closed: ridges(RidgeKind::Valley, true),
            p_min: points(ExtremumKind::Min),
            p_max: points(ExtremumKind::Max),
            saddles: ls.saddles.iter().map(|s| s.m()).collect(),
            lminus_outer,
            lminus_hole,
            lminus_area,
            lminus_area_approx,
            lplus_outer,
            lplus_hole,
            lplus_area,
            lplus_area_approx,
        }
    }
}

#[derive(Serialize)]
struct LayerData {
    heading: String,
    note: String,
    z: String,
    approx: f64,
    #[serde(rename = "viewBox")]
    view_box: String,
    frame: String,
    svg: String,
    counts: Counts,
}

#[derive(Serialize)]
struct ViewerData<'a> {
    format: &'static str,
    version: u32,
    arrows: bool,
    layers: Vec<LayerData>,
    critical: &'a [CriticalMark],
    /// Critical heights not listed (beyond [`MAX_MARKS`]).
    unlisted: usize,
}

/// JSON text safe inside a `<script>` element: every `<` is escaped (it can
/// only occur inside JSON strings, where `\u003c` means the same).
fn script_safe_json(json: &str) -> String {
    json.replace('<', "\\u003c")
}

/// The page's own style (the drawing's classes come from [`style`]).
const PAGE_STYLE: &str = "\
html,body{margin:0;height:100%}
body{font:13px sans-serif;color:#222;background:#fff}
#top{position:absolute;left:0;top:0;right:0;height:84px;padding:6px 10px;box-sizing:border-box;border-bottom:1px solid #ccc;overflow:hidden}
#top div{margin:2px 0;white-space:nowrap;overflow:hidden;text-overflow:ellipsis}
#slider{width:260px;vertical-align:middle}
#level{font-weight:bold;font-size:15px}
#toggles label{margin-right:9px;cursor:pointer}
.sw{display:inline-block;width:14px;height:10px;margin:0 3px 0 1px;border:1px solid #555;vertical-align:middle}
#view{position:absolute;left:8px;top:92px;width:calc(100vw - 284px);height:calc(100vh - 100px);background:#fff}
#side{position:absolute;right:0;top:84px;bottom:0;width:268px;overflow:auto;padding:8px 10px;box-sizing:border-box;border-left:1px solid #ccc}
#counts{border-collapse:collapse}
#counts td{padding:1px 6px 1px 0;vertical-align:top}
#counts td.n{text-align:right;font-variant-numeric:tabular-nums}
.hint{color:#666;font-size:12px}
#critical ul{margin:2px 0;padding-left:16px}
#critical li.here{font-weight:bold;background:#fff3b0}
#critical a{cursor:pointer;color:#1a4fa0;text-decoration:underline}
body.hide-so .layer-so,body.hide-f .layer-f,body.hide-sno .layer-sno,body.hide-p .layer-p,body.hide-saddle .layer-saddle,body.hide-lminus .layer-lminus,body.hide-lplus .layer-lplus{display:none}
body:not(.arrows) .arrow{display:none}
";

/// The viewer's script (no external resources, ES5).
const SCRIPT: &str = r#"(function () {
  'use strict';
  var D = JSON.parse(document.getElementById('data').textContent);
  var L = D.layers, n = L.length, cur = 0;
  var KINDS = ['so', 'f', 'sno', 'p', 'saddle', 'lminus', 'lplus', 'arrows'];
  var on = {so: 1, f: 1, sno: 1, p: 1, saddle: 1, lminus: 1, lplus: 1, arrows: D.arrows ? 1 : 0};
  function $(id) { return document.getElementById(id); }
  var view = $('view'), slider = $('slider'), body = document.body;
  function readHash() {
    var h = location.hash.replace(/^#/, '');
    if (!h) { return; }
    h.split('&').forEach(function (kv) {
      var i = kv.indexOf('=');
      var k = i < 0 ? kv : kv.slice(0, i);
      var v = i < 0 ? '1' : decodeURIComponent(kv.slice(i + 1));
      if (k === 'layer') {
        var x = parseInt(v, 10);
        if (!isNaN(x)) { cur = x; }
      } else if (k === 'z') {
        for (var j = 0; j < n; j++) { if (L[j].z === v) { cur = j; break; } }
      } else if (Object.prototype.hasOwnProperty.call(on, k)) {
        on[k] = (v === '0' || v === 'false' || v === 'off') ? 0 : 1;
      }
    });
  }
  function writeHash() {
    var s = 'layer=' + cur;
    KINDS.forEach(function (k) { s += '&' + k + '=' + on[k]; });
    try { history.replaceState(null, '', '#' + s); } catch (e) { /* file:// in some browsers */ }
  }
  function applyToggles() {
    KINDS.forEach(function (k) {
      if (k === 'arrows') { body.classList.toggle('arrows', !!on[k]); }
      else { body.classList.toggle('hide-' + k, !on[k]); }
      var box = $('t-' + k);
      if (box) { box.checked = !!on[k]; }
    });
  }
  function row(label, value) {
    return '<tr><td>' + label + '</td><td class="n">' + value + '</td></tr>';
  }
  function esc(s) {
    return String(s).replace(/&/g, '&amp;').replace(/</g, '&lt;').replace(/>/g, '&gt;');
  }
  // An exact area as written when short, else its nearest double, with
  // the exact value on hover.
  function area(exact, approx) {
    if (exact.length <= 24) { return esc(exact); }
    return '<span title="' + esc(exact) + '">~' + esc(approx) + '</span>';
  }
  function countsTable(c) {
    var sad = c.saddles.length ? c.saddles.length + ' (m = ' + c.saddles.join(', ') + ')' : '0';
    return row('S_O outer / hole', c.so_outer + ' / ' + c.so_hole) +
      row('S_O area', area(c.so_area, c.so_area_approx)) +
      row('F up / down / flat', c.f_up + ' / ' + c.f_down + ' / ' + c.f_flat) +
      row('dF loops', c.df) +
      row('S_NO ridges open / closed', c.ridge_open + ' / ' + c.ridge_closed) +
      row('S_NO valleys open / closed', c.valley_open + ' / ' + c.valley_closed) +
      row('P min / max', c.p_min + ' / ' + c.p_max) +
      row('saddles', sad) +
      row('L- outer / hole', c.lminus_outer + ' / ' + c.lminus_hole) +
      row('L- area', area(c.lminus_area, c.lminus_area_approx)) +
      row('L+ outer / hole', c.lplus_outer + ' / ' + c.lplus_hole) +
      row('L+ area', area(c.lplus_area, c.lplus_area_approx));
  }
  function show(i) {
    if (n === 0) { $('level').textContent = '(no layers)'; return; }
    cur = Math.max(0, Math.min(n - 1, i | 0));
    var l = L[cur];
    view.setAttribute('viewBox', l.viewBox);
    view.setAttribute('data-frame', l.frame);
    view.innerHTML = l.svg;
    // A level too long for the heading (hundreds of digits on a part at
    // 1e-300) shows its nearest double; the exact level is on hover.
    if (l.z.length <= 40) {
      $('level').textContent = l.z;
      $('level').removeAttribute('title');
      $('approx').textContent = '(~' + l.approx + ')';
    } else {
      $('level').textContent = '~' + l.approx;
      $('level').setAttribute('title', l.z);
      $('approx').textContent = '(exact on hover)';
    }
    $('heading').textContent = l.heading;
    $('note').textContent = l.note;
    $('index').textContent = String(cur);
    $('counts').innerHTML = countsTable(l.counts);
    slider.value = String(cur);
    body.setAttribute('data-layer', String(cur));
    markCritical();
    writeHash();
  }
  function criticalList() {
    var C = D.critical, box = $('critical');
    if (!C.length) { return; }
    var h = '<p><b>critical heights</b> (' + (C.length + D.unlisted) + ')</p><ul>';
    C.forEach(function (c) {
      var j = -1;
      for (var k = 0; k < n; k++) { if (L[k].z === c.z) { j = k; break; } }
      var t = esc(c.z) + ' <span class="hint">~' + esc(c.approx) + '</span>: ' + esc(c.holds);
      h += '<li data-z="' + esc(c.z) + '">' + (j < 0 ? t : '<a data-to="' + j + '">' + t + '</a>') + '</li>';
    });
    if (D.unlisted) { h += '<li class="hint">and ' + D.unlisted + ' more (wmslice critical)</li>'; }
    box.innerHTML = h + '</ul>';
    box.addEventListener('click', function (e) {
      var a = e.target.closest ? e.target.closest('a[data-to]') : null;
      if (a) { e.preventDefault(); show(parseInt(a.getAttribute('data-to'), 10)); }
    });
  }
  function markCritical() {
    var items = $('critical').getElementsByTagName('li');
    for (var k = 0; k < items.length; k++) {
      items[k].classList.toggle('here', n > 0 && items[k].getAttribute('data-z') === L[cur].z);
    }
  }
  function step(d) { show(cur + d); }
  slider.max = String(Math.max(0, n - 1));
  slider.addEventListener('input', function () { show(parseInt(slider.value, 10)); });
  $('prev').addEventListener('click', function () { step(-1); });
  $('next').addEventListener('click', function () { step(1); });
  KINDS.forEach(function (k) {
    var box = $('t-' + k);
    box.addEventListener('change', function () { on[k] = box.checked ? 1 : 0; applyToggles(); writeHash(); });
  });
  document.addEventListener('keydown', function (e) {
    if (e.target === slider || e.altKey || e.ctrlKey || e.metaKey) { return; }
    var d = {ArrowLeft: -1, ArrowDown: -1, ArrowRight: 1, ArrowUp: 1, PageUp: 10, PageDown: -10}[e.key];
    if (e.key === 'Home') { show(0); } else if (e.key === 'End') { show(n - 1); }
    else if (d) { step(d); } else { return; }
    e.preventDefault();
  });
  window.addEventListener('hashchange', function () { readHash(); applyToggles(); show(cur); });
  criticalList();
  readHash();
  applyToggles();
  show(cur);
  var r = view.getBoundingClientRect();
  body.setAttribute('data-view-rect', [r.left, r.top, r.width, r.height].map(Math.round).join(','));
  body.setAttribute('data-ready', '1');
})();
"#;

/// The toggles: fragment key, label, swatch colour.
fn toggles() -> [(&'static str, &'static str, &'static str); 8] {
    use super::svg::colour::*;
    [
        ("so", "S_O", SO_OUTER),
        ("f", "F + dF", F_UP),
        ("sno", "S_NO", RIDGE),
        ("p", "P", P_MAX),
        ("saddle", "saddles", SADDLE),
        ("lminus", "L-", L_MINUS),
        ("lplus", "L+", L_PLUS),
        ("arrows", "arrows", "#ffffff"),
    ]
}

/// The complete viewer page of `layers`, in the order given.
pub fn viewer(layers: &[ViewerLayer], opts: &ViewerOptions) -> String {
    let svg_opts = SvgOptions { arrows: true };
    let data = ViewerData {
        format: "wmslice-viewer",
        version: 1,
        arrows: opts.arrows,
        layers: layers
            .iter()
            .map(|l| {
                let d = drawing(l.level, l.scene, &svg_opts);
                LayerData {
                    heading: l.heading.clone(),
                    note: l.note.clone(),
                    z: rat_to_string(&l.level.level),
                    approx: rat_to_f64(&l.level.level),
                    view_box: d.view_box_attr(),
                    frame: d.frame.attr(),
                    svg: d.body,
                    counts: Counts::of(l.level),
                }
            })
            .collect(),
        critical: &opts.critical,
        unlisted: opts.unlisted_marks,
    };
    // Serializing plain strings and numbers cannot fail; fall back to an
    // empty document rather than panicking.
    let json = serde_json::to_string(&data).unwrap_or_else(|_| "{\"layers\":[]}".into());
    let mut toggles_html = String::new();
    for (key, label, col) in toggles() {
        toggles_html.push_str(&format!(
            r#"<label><input type="checkbox" id="t-{key}" checked><span class="sw" style="background:{col}"></span>{label}</label>"#
        ));
    }
    let n = layers.len();
    let layers_text = if n == 1 {
        "1 layer".to_string()
    } else {
        format!("{n} layers")
    };
    format!(
        r#"<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>{title}</title>
<style>
{page}{drawing}</style>
</head>
<body>
<div id="top">
<div><b id="heading"></b> <span id="note"></span></div>
<div><button id="prev" title="previous layer (Left)">&#9664;</button> <input type="range" id="slider" min="0" max="{max}" step="1" value="0"> <button id="next" title="next layer (Right)">&#9654;</button> layer <span id="index">0</span> of 0..{max} &nbsp; z = <span id="level"></span> <span id="approx"></span></div>
<div id="toggles">{toggles_html}</div>
</div>
<svg id="view" xmlns="http://www.w3.org/2000/svg" preserveAspectRatio="xMidYMid meet" viewBox="0 0 1 1"></svg>
<div id="side">
<table id="counts"></table>
<div id="critical"></div>
<p class="hint" title="PageUp/PageDown step by 10; the URL fragment keeps the layer and the toggles">{layers_text}; keys Left/Right, Home/End</p>
</div>
<script type="application/json" id="data">{json}</script>
<script>
{script}</script>
</body>
</html>
"#,
        title = xml_escape(&opts.title),
        page = PAGE_STYLE,
        drawing = style(),
        max = n.saturating_sub(1),
        json = script_safe_json(&json),
        script = SCRIPT,
    )
}

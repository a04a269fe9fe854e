//! CLI bytes, ASCII or binary, to a typed [`CliFile`]: every defect a
//! [`CliError`] naming where it is; no allocation beyond the input's size.

use super::*;

/// What is wrong with a command's parameters or a binary value.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum Problem {
    /// A value does not parse as a number.
    #[error("a value is not a number")]
    NotANumber,
    /// A value is infinite or NaN.
    #[error("a value is not finite")]
    NotFinite,
    /// A count, id or code is not an integer in range.
    #[error("a count, id or code is not an integer in range")]
    NotAnInteger,
    /// Fewer or more values than the command takes.
    #[error("expected {expected} values, found {found}")]
    ValueCount {
        /// Expected.
        expected: usize,
        /// Found.
        found: usize,
    },
    /// The direction is not 0, 1 or 2.
    #[error("direction {0} is not 0, 1 or 2")]
    Direction(i64),
    /// A declared count is negative.
    #[error("negative count {0}")]
    NegativeCount(i64),
    /// `$$UNITS` is not positive.
    #[error("units must be positive")]
    NonPositiveUnits,
}

/// Why a CLI file cannot be read.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum CliError {
    /// The file does not start with `$$HEADERSTART`.
    #[error("not a CLI file: it does not start with $$HEADERSTART")]
    NotCli,
    /// No `$$HEADEREND`.
    #[error("the header has no $$HEADEREND")]
    MissingHeaderEnd,
    /// Neither `$$ASCII` nor `$$BINARY`.
    #[error("the header says neither $$ASCII nor $$BINARY")]
    MissingEncoding,
    /// Both `$$ASCII` and `$$BINARY`.
    #[error("the header says both $$ASCII and $$BINARY")]
    ConflictingEncoding,
    /// `$$ALIGN` (4-byte aligned binary data) is not supported.
    #[error("$$ALIGN binary files are not supported")]
    AlignUnsupported,
    /// A command's parameters are wrong.
    #[error("line {line}: $${command}: {problem}")]
    BadParameters {
        /// 1-based line.
        line: usize,
        /// The command (without `$$`).
        command: String,
        /// What is wrong.
        problem: Problem,
    },
    /// An unknown geometry command.
    #[error("line {line}: unknown geometry command $${command}")]
    UnknownCommand {
        /// 1-based line.
        line: usize,
        /// The command (without `$$`).
        command: String,
    },
    /// Text that is not a `$$` command.
    #[error("line {line}: text outside any command")]
    StrayText {
        /// 1-based line.
        line: usize,
    },
    /// Geometry before the first `$$LAYER`.
    #[error("line {line}: $${command} before the first $$LAYER")]
    OutsideLayer {
        /// 1-based line.
        line: usize,
        /// The command.
        command: String,
    },
    /// Binary geometry before the first layer command.
    #[error("byte {offset}: {what} before the first layer")]
    OutsideLayerAt {
        /// Offset of the command.
        offset: usize,
        /// The command.
        what: &'static str,
    },
    /// ASCII geometry does not start with `$$GEOMETRYSTART`.
    #[error("line {line}: expected $$GEOMETRYSTART")]
    MissingGeometryStart {
        /// 1-based line.
        line: usize,
    },
    /// ASCII geometry does not end with `$$GEOMETRYEND`.
    #[error("no $$GEOMETRYEND")]
    MissingGeometryEnd,
    /// Commands after `$$GEOMETRYEND`.
    #[error("line {line}: commands after $$GEOMETRYEND")]
    AfterGeometryEnd {
        /// 1-based line.
        line: usize,
    },
    /// A layer lies below the one before it.
    #[error("layer {index}: z = {z} is below the previous layer's z = {previous}")]
    NotAscending {
        /// 0-based layer index.
        index: usize,
        /// Its z.
        z: f64,
        /// The previous layer's z.
        previous: f64,
    },
    /// `$$LAYERS` disagrees with the layers in the file.
    #[error("$$LAYERS/{declared} but the file holds {found} layers")]
    LayerCount {
        /// Declared.
        declared: u64,
        /// Found.
        found: usize,
    },
    /// An unknown binary command code.
    #[error("byte {offset}: unknown binary command code {code}")]
    UnknownCode {
        /// Offset of the code.
        offset: usize,
        /// The code.
        code: u16,
    },
    /// Binary data ends inside a command.
    #[error("byte {offset}: {what} needs {needed} bytes, only {available} left")]
    Truncated {
        /// Offset where the data was expected.
        offset: usize,
        /// What was being read.
        what: &'static str,
        /// Bytes needed.
        needed: u64,
        /// Bytes left.
        available: usize,
    },
    /// A wrong binary value.
    #[error("byte {offset}: {what}: {problem}")]
    BadBinary {
        /// Offset of the command.
        offset: usize,
        /// The command.
        what: &'static str,
        /// What is wrong.
        problem: Problem,
    },
}

/// One `$$` command of the ASCII text.
struct Command {
    line: usize,
    name: String,
    params: String,
}

/// Splits text into `$$` commands: comments removed, line breaks inside a
/// command's parameters joined. `first_line` is the 1-based line of the
/// text's start.
fn commands(text: &str, first_line: usize) -> Result<Vec<Command>, CliError> {
    let mut out: Vec<Command> = Vec::new();
    for (i, raw) in text.split('\n').enumerate() {
        let line = first_line + i;
        let code = strip_comments(raw.trim_end_matches('\r'));
        let mut rest = code.as_str();
        if let Some(pos) = rest.find("$$") {
            let before = rest[..pos].trim();
            if !before.is_empty() {
                match out.last_mut() {
                    Some(c) => c.params.push_str(before),
                    None => return Err(CliError::StrayText { line }),
                }
            }
            rest = &rest[pos..];
        } else {
            let t = rest.trim();
            if !t.is_empty() {
                match out.last_mut() {
                    Some(c) => c.params.push_str(t),
                    None => return Err(CliError::StrayText { line }),
                }
            }
            continue;
        }
        for piece in rest.split("$$").skip(1) {
            let (name, params) = match piece.find('/') {
                Some(p) => (&piece[..p], &piece[p + 1..]),
                None => (piece, ""),
            };
            out.push(Command {
                line,
                name: name.trim().to_ascii_uppercase(),
                params: params.trim().to_string(),
            });
        }
    }
    Ok(out)
}

/// A line without its `// ... //` comments (a comment runs to the next
/// `//` or to the end of the line).
fn strip_comments(line: &str) -> String {
    let mut out = String::new();
    let mut rest = line;
    while let Some(p) = rest.find("//") {
        out.push_str(&rest[..p]);
        rest = &rest[p + 2..];
        match rest.find("//") {
            Some(q) => rest = &rest[q + 2..],
            None => return out,
        }
    }
    out.push_str(rest);
    out
}

fn split_params(c: &Command) -> Vec<&str> {
    if c.params.trim().is_empty() {
        return Vec::new();
    }
    c.params.split(',').map(str::trim).collect()
}

fn bad(c: &Command, problem: Problem) -> CliError {
    CliError::BadParameters {
        line: c.line,
        command: c.name.clone(),
        problem,
    }
}

fn real(c: &Command, t: &str) -> Result<f64, CliError> {
    let x: f64 = t.parse().map_err(|_| bad(c, Problem::NotANumber))?;
    if x.is_finite() {
        Ok(x)
    } else {
        Err(bad(c, Problem::NotFinite))
    }
}

fn integer(c: &Command, t: &str) -> Result<i64, CliError> {
    t.parse::<i64>().map_err(|_| bad(c, Problem::NotAnInteger))
}

fn exactly<'a>(c: &Command, v: &'a [&'a str], n: usize) -> Result<&'a [&'a str], CliError> {
    if v.len() == n {
        Ok(v)
    } else {
        Err(bad(
            c,
            Problem::ValueCount {
                expected: n,
                found: v.len(),
            },
        ))
    }
}

fn id_i32(c: &Command, t: &str) -> Result<i32, CliError> {
    i32::try_from(integer(c, t)?).map_err(|_| bad(c, Problem::NotAnInteger))
}

fn parse_header(cmds: &[Command]) -> Result<Header, CliError> {
    let mut encoding = None;
    let mut h = Header {
        encoding: Encoding::Ascii,
        units: 1.0,
        version: 0,
        labels: Vec::new(),
        date: None,
        dimension: None,
        layers: None,
        other: Vec::new(),
    };
    for (i, c) in cmds.iter().enumerate() {
        let v = split_params(c);
        match c.name.as_str() {
            "HEADERSTART" if i == 0 => {}
            "ASCII" | "BINARY" => {
                let e = if c.name == "ASCII" {
                    Encoding::Ascii
                } else {
                    Encoding::Binary
                };
                if encoding.is_some_and(|x| x != e) {
                    return Err(CliError::ConflictingEncoding);
                }
                encoding = Some(e);
            }
            "ALIGN" => return Err(CliError::AlignUnsupported),
            "UNITS" => {
                let u = real(c, exactly(c, &v, 1)?[0])?;
                if u <= 0.0 {
                    return Err(bad(c, Problem::NonPositiveUnits));
                }
                h.units = u;
            }
            "VERSION" => {
                let x = integer(c, exactly(c, &v, 1)?[0])?;
                h.version = u32::try_from(x).map_err(|_| bad(c, Problem::NotAnInteger))?;
            }
            "LABEL" => {
                let (id, text) = match c.params.split_once(',') {
                    Some((a, b)) => (a, b),
                    None => {
                        return Err(bad(
                            c,
                            Problem::ValueCount {
                                expected: 2,
                                found: 1,
                            },
                        ))
                    }
                };
                h.labels
                    .push((id_i32(c, id.trim())?, text.trim().to_string()));
            }
            "DATE" => h.date = Some(c.params.trim().to_string()),
            "DIMENSION" => {
                let v = exactly(c, &v, 6)?;
                let mut d = [0.0; 6];
                for (k, t) in v.iter().enumerate() {
                    d[k] = real(c, t)?;
                }
                h.dimension = Some(d);
            }
            "LAYERS" => {
                let x = integer(c, exactly(c, &v, 1)?[0])?;
                h.layers = Some(u64::try_from(x).map_err(|_| bad(c, Problem::NegativeCount(x)))?);
            }
            _ => h.other.push(if c.params.is_empty() {
                c.name.clone()
            } else {
                format!("{}/{}", c.name, c.params)
            }),
        }
    }
    h.encoding = encoding.ok_or(CliError::MissingEncoding)?;
    Ok(h)
}

/// Checks that layer `index` at `z` is not below the previous one.
fn check_ascending(layers: &[Layer], z: f64) -> Result<(), CliError> {
    if let Some(prev) = layers.last() {
        if z < prev.z {
            return Err(CliError::NotAscending {
                index: layers.len(),
                z,
                previous: prev.z,
            });
        }
    }
    Ok(())
}

fn parse_ascii_geometry(cmds: &[Command]) -> Result<Vec<Layer>, CliError> {
    let mut it = cmds.iter();
    match it.next() {
        Some(c) if c.name == "GEOMETRYSTART" => {}
        Some(c) => return Err(CliError::MissingGeometryStart { line: c.line }),
        None => return Err(CliError::MissingGeometryEnd),
    }
    let mut layers: Vec<Layer> = Vec::new();
    let mut ended = false;
    for c in it {
        if ended {
            return Err(CliError::AfterGeometryEnd { line: c.line });
        }
        let v = split_params(c);
        match c.name.as_str() {
            "GEOMETRYEND" => ended = true,
            "LAYER" => {
                let z = real(c, exactly(c, &v, 1)?[0])?;
                check_ascending(&layers, z)?;
                layers.push(Layer {
                    z,
                    polylines: Vec::new(),
                    hatches: Vec::new(),
                });
            }
            "POLYLINE" | "HATCHES" => {
                let per = if c.name == "POLYLINE" { 2 } else { 4 };
                let head = if c.name == "POLYLINE" { 3 } else { 2 };
                if v.len() < head {
                    return Err(bad(
                        c,
                        Problem::ValueCount {
                            expected: head,
                            found: v.len(),
                        },
                    ));
                }
                let id = id_i32(c, v[0])?;
                let n = integer(c, v[head - 1])?;
                if n < 0 {
                    return Err(bad(c, Problem::NegativeCount(n)));
                }
                let values = &v[head..];
                // n is bounded by the values present, never trusted first.
                if (values.len() as u128) != (n as u128) * per as u128 {
                    return Err(bad(
                        c,
                        Problem::ValueCount {
                            expected: head + (n as usize).saturating_mul(per),
                            found: v.len(),
                        },
                    ));
                }
                let nums = values
                    .iter()
                    .map(|t| real(c, t))
                    .collect::<Result<Vec<f64>, _>>()?;
                let layer = layers.last_mut().ok_or_else(|| CliError::OutsideLayer {
                    line: c.line,
                    command: c.name.clone(),
                })?;
                if c.name == "POLYLINE" {
                    let d = integer(c, v[1])?;
                    let dir =
                        Direction::from_code(d).ok_or_else(|| bad(c, Problem::Direction(d)))?;
                    layer.polylines.push(Polyline {
                        id,
                        dir,
                        points: nums.chunks_exact(2).map(|p| [p[0], p[1]]).collect(),
                    });
                } else {
                    layer.hatches.push(Hatches {
                        id,
                        lines: nums
                            .chunks_exact(4)
                            .map(|p| [[p[0], p[1]], [p[2], p[3]]])
                            .collect(),
                    });
                }
            }
            _ => {
                return Err(CliError::UnknownCommand {
                    line: c.line,
                    command: c.name.clone(),
                })
            }
        }
    }
    if !ended {
        return Err(CliError::MissingGeometryEnd);
    }
    Ok(layers)
}

/// A cursor over binary geometry.
struct Bin<'a> {
    data: &'a [u8],
    base: usize,
    pos: usize,
}

impl<'a> Bin<'a> {
    fn offset(&self) -> usize {
        self.base + self.pos
    }

    fn left(&self) -> usize {
        self.data.len() - self.pos
    }

    fn need(&self, bytes: u64, what: &'static str) -> Result<(), CliError> {
        if bytes > self.left() as u64 {
            Err(CliError::Truncated {
                offset: self.offset(),
                what,
                needed: bytes,
                available: self.left(),
            })
        } else {
            Ok(())
        }
    }

    fn take<const N: usize>(&mut self, what: &'static str) -> Result<[u8; N], CliError> {
        self.need(N as u64, what)?;
        let mut b = [0u8; N];
        b.copy_from_slice(&self.data[self.pos..self.pos + N]);
        self.pos += N;
        Ok(b)
    }

    fn u16(&mut self, what: &'static str) -> Result<u16, CliError> {
        Ok(u16::from_le_bytes(self.take(what)?))
    }

    fn i32(&mut self, what: &'static str) -> Result<i32, CliError> {
        Ok(i32::from_le_bytes(self.take(what)?))
    }

    fn f32(&mut self, what: &'static str, at: usize) -> Result<f64, CliError> {
        let x = f32::from_le_bytes(self.take(what)?);
        if x.is_finite() {
            Ok(f64::from(x))
        } else {
            Err(CliError::BadBinary {
                offset: at,
                what,
                problem: Problem::NotFinite,
            })
        }
    }
}

fn count_of(n: i64, at: usize, what: &'static str) -> Result<u64, CliError> {
    u64::try_from(n).map_err(|_| CliError::BadBinary {
        offset: at,
        what,
        problem: Problem::NegativeCount(n),
    })
}

fn parse_binary_geometry(data: &[u8], base: usize) -> Result<Vec<Layer>, CliError> {
    let mut b = Bin { data, base, pos: 0 };
    let mut layers: Vec<Layer> = Vec::new();
    while b.left() > 0 {
        let at = b.offset();
        let c = b.u16("command code")?;
        let outside = |what: &'static str| CliError::OutsideLayerAt { offset: at, what };
        match c {
            code::LAYER_LONG | code::LAYER_SHORT => {
                let z = if c == code::LAYER_LONG {
                    b.f32("layer long", at)?
                } else {
                    f64::from(b.u16("layer short")?)
                };
                check_ascending(&layers, z)?;
                layers.push(Layer {
                    z,
                    polylines: Vec::new(),
                    hatches: Vec::new(),
                });
            }
            code::POLYLINE_LONG | code::POLYLINE_SHORT => {
                let long = c == code::POLYLINE_LONG;
                let what = if long {
                    "polyline long"
                } else {
                    "polyline short"
                };
                let (id, d, n) = if long {
                    (
                        b.i32(what)?,
                        i64::from(b.i32(what)?),
                        i64::from(b.i32(what)?),
                    )
                } else {
                    (
                        i32::from(b.u16(what)?),
                        i64::from(b.u16(what)?),
                        i64::from(b.u16(what)?),
                    )
                };
                let dir = Direction::from_code(d).ok_or(CliError::BadBinary {
                    offset: at,
                    what,
                    problem: Problem::Direction(d),
                })?;
                let n = count_of(n, at, what)?;
                let size = if long { 8 } else { 4 };
                b.need(n * size, what)?;
                let mut points = Vec::with_capacity(n as usize);
                for _ in 0..n {
                    points.push(if long {
                        [b.f32(what, at)?, b.f32(what, at)?]
                    } else {
                        [f64::from(b.u16(what)?), f64::from(b.u16(what)?)]
                    });
                }
                layers
                    .last_mut()
                    .ok_or_else(|| outside(what))?
                    .polylines
                    .push(Polyline { id, dir, points });
            }
            code::HATCHES_LONG | code::HATCHES_SHORT => {
                let long = c == code::HATCHES_LONG;
                let what = if long {
                    "hatches long"
                } else {
                    "hatches short"
                };
                let (id, n) = if long {
                    (b.i32(what)?, i64::from(b.i32(what)?))
                } else {
                    (i32::from(b.u16(what)?), i64::from(b.u16(what)?))
                };
                let n = count_of(n, at, what)?;
                let size = if long { 16 } else { 8 };
                b.need(n * size, what)?;
                let mut lines = Vec::with_capacity(n as usize);
                for _ in 0..n {
                    let mut v = [0.0; 4];
                    for x in &mut v {
                        *x = if long {
                            b.f32(what, at)?
                        } else {
                            f64::from(b.u16(what)?)
                        };
                    }
                    lines.push([[v[0], v[1]], [v[2], v[3]]]);
                }
                layers
                    .last_mut()
                    .ok_or_else(|| outside(what))?
                    .hatches
                    .push(Hatches { id, lines });
            }
            _ => {
                return Err(CliError::UnknownCode {
                    offset: at,
                    code: c,
                })
            }
        }
    }
    Ok(layers)
}

fn find(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).position(|w| w == needle)
}

/// Where `$$HEADERSTART` should be: after a byte-order mark, white space
/// and `//` comments.
fn header_start(bytes: &[u8]) -> usize {
    let mut i = if bytes.starts_with(b"\xEF\xBB\xBF") {
        3
    } else {
        0
    };
    loop {
        while i < bytes.len() && bytes[i].is_ascii_whitespace() {
            i += 1;
        }
        if !bytes[i..].starts_with(b"//") {
            return i;
        }
        i += 2;
        let line_end = bytes[i..]
            .iter()
            .position(|&b| b == b'\n')
            .map_or(bytes.len(), |p| i + p);
        i = match find(&bytes[i..line_end], b"//") {
            Some(p) => i + p + 2,
            None => line_end,
        };
    }
}

/// Reads a CLI file, ASCII or binary (told apart by its header).
pub fn read(bytes: &[u8]) -> Result<CliFile, CliError> {
    let start = header_start(bytes);
    if !bytes[start..].starts_with(b"$$HEADERSTART") {
        return Err(CliError::NotCli);
    }
    const END: &[u8] = b"$$HEADEREND";
    let end = find(&bytes[start..], END)
        .map(|p| p + start)
        .ok_or(CliError::MissingHeaderEnd)?;
    let header_text = String::from_utf8_lossy(&bytes[start..end]);
    let first_line = 1 + bytes[..start].iter().filter(|&&b| b == b'\n').count();
    let header = parse_header(&commands(&header_text, first_line)?)?;
    let after = end + END.len();
    let layers = match header.encoding {
        Encoding::Binary => {
            // An optional line break after $$HEADEREND (no command code
            // starts with byte 10 or 13).
            let mut skip = after;
            while skip < bytes.len() && skip < after + 2 && matches!(bytes[skip], b'\r' | b'\n') {
                skip += 1;
            }
            parse_binary_geometry(&bytes[skip..], skip)?
        }
        Encoding::Ascii => {
            let text = String::from_utf8_lossy(&bytes[after..]);
            let line = 1 + bytes[..after].iter().filter(|&&b| b == b'\n').count();
            parse_ascii_geometry(&commands(&text, line)?)?
        }
    };
    if let Some(declared) = header.layers {
        if declared != layers.len() as u64 {
            return Err(CliError::LayerCount {
                declared,
                found: layers.len(),
            });
        }
    }
    Ok(CliFile { header, layers })
}

//! Input: JSON text. Output: a [`Value`] tree that keeps every number as the
//! exact text of the file, and the text again ([`Value::to_json`]).
//!
//! The verifier reads its own JSON instead of going through `serde_json`
//! because a checker of exact results must know the exact number that was
//! written: `serde_json`'s default float parsing is best-effort and may land
//! one unit in the last place away from the written decimal. Here a number
//! stays text; the verifier turns it into an exact rational. Strict RFC 8259
//! syntax, duplicate keys refused, nesting bounded by [`MAX_DEPTH`] (no
//! recursion can overflow the stack).

use std::fmt::{self, Write};

/// The deepest accepted nesting of arrays and objects.
pub const MAX_DEPTH: usize = 128;

/// A JSON value; numbers keep their text, objects their key order.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Value {
    /// `null`.
    Null,
    /// `true` or `false`.
    Bool(bool),
    /// A number, exactly as written (valid JSON number syntax).
    Number(String),
    /// A string (escapes decoded).
    String(String),
    /// An array.
    Array(Vec<Value>),
    /// An object, keys in file order (no duplicates).
    Object(Vec<(String, Value)>),
}

/// What is wrong with the JSON text.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum JsonErrorKind {
    /// The text ends inside a value.
    UnexpectedEnd,
    /// A character that cannot start or continue what is being read.
    UnexpectedChar(char),
    /// A number that does not follow JSON's number syntax.
    BadNumber,
    /// A bad escape sequence or control character in a string.
    BadString,
    /// The same key twice in one object.
    DuplicateKey(String),
    /// Nesting deeper than [`MAX_DEPTH`].
    TooDeep,
    /// Something after the top-level value.
    TrailingCharacters,
}

impl fmt::Display for JsonErrorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            JsonErrorKind::UnexpectedEnd => f.write_str("unexpected end of text"),
            JsonErrorKind::UnexpectedChar(c) => write!(f, "unexpected character {c:?}"),
            JsonErrorKind::BadNumber => f.write_str("malformed number"),
            JsonErrorKind::BadString => f.write_str("malformed string (escape or control char)"),
            JsonErrorKind::DuplicateKey(k) => write!(f, "duplicate key {k:?}"),
            JsonErrorKind::TooDeep => write!(f, "nested deeper than {MAX_DEPTH} levels"),
            JsonErrorKind::TrailingCharacters => f.write_str("text after the JSON value"),
        }
    }
}

/// A JSON syntax error with its 1-based line and column.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("not valid JSON: {kind} at line {line}, column {column}")]
pub struct JsonError {
    /// What is wrong.
    pub kind: JsonErrorKind,
    /// 1-based line.
    pub line: usize,
    /// 1-based column (in characters).
    pub column: usize,
}

/// Parses a whole JSON text.
///
/// ```
/// use wmslice::verify::json::{parse, Value};
/// let v = parse(r#"{"x": [0.1, -2e3]}"#).unwrap();
/// assert_eq!(v.get("x").unwrap().as_array().unwrap()[0], Value::Number("0.1".into()));
/// assert!(parse("{\"a\": 1, \"a\": 2}").is_err());
/// ```
pub fn parse(text: &str) -> Result<Value, JsonError> {
    let mut p = Parser {
        s: text.as_bytes(),
        text,
        i: 0,
    };
    p.ws();
    let v = p.value()?;
    p.end()?;
    Ok(v)
}

/// Parses a JSON text whose top level is an object, without building the
/// array under its key `key`: each element of that array is parsed and
/// handed to `each` with its index, then dropped, so memory holds one
/// element at a time (a result's levels); the returned object has an empty
/// array there. Any other text parses as with [`parse`].
pub fn parse_streaming<E: From<JsonError>>(
    text: &str,
    key: &str,
    mut each: impl FnMut(usize, Value) -> Result<(), E>,
) -> Result<Value, E> {
    let mut p = Parser {
        s: text.as_bytes(),
        text,
        i: 0,
    };
    p.ws();
    if p.peek() != Some(b'{') {
        let v = p.value()?;
        p.end()?;
        return Ok(v);
    }
    p.i += 1;
    p.ws();
    let mut fields: Vec<(String, Value)> = Vec::new();
    if p.peek() == Some(b'}') {
        p.i += 1;
    } else {
        loop {
            let k = p.key()?;
            if fields.iter().any(|(f, _)| *f == k) {
                return Err(p.err(JsonErrorKind::DuplicateKey(k)).into());
            }
            p.ws();
            let v = if k == key && p.peek() == Some(b'[') {
                p.i += 1;
                p.ws();
                if p.peek() == Some(b']') {
                    p.i += 1;
                } else {
                    let mut n = 0;
                    loop {
                        each(n, p.value()?)?;
                        n += 1;
                        p.ws();
                        match p.peek() {
                            Some(b',') => p.i += 1,
                            Some(b']') => {
                                p.i += 1;
                                break;
                            }
                            _ => return Err(p.unexpected().into()),
                        }
                    }
                }
                Value::Array(Vec::new())
            } else {
                p.value()?
            };
            fields.push((k, v));
            p.ws();
            match p.peek() {
                Some(b',') => p.i += 1,
                Some(b'}') => {
                    p.i += 1;
                    break;
                }
                _ => return Err(p.unexpected().into()),
            }
        }
    }
    p.end()?;
    Ok(Value::Object(fields))
}

/// An array or object being filled while parsing (the explicit stack).
enum Open {
    Array(Vec<Value>),
    Object(Vec<(String, Value)>, String),
}

struct Parser<'a> {
    s: &'a [u8],
    text: &'a str,
    i: usize,
}

impl Parser<'_> {
    fn err(&self, kind: JsonErrorKind) -> JsonError {
        // An error may stop inside a character (after `\` comes its first
        // byte): the position is that character's.
        let mut end = self.i.min(self.text.len());
        while !self.text.is_char_boundary(end) {
            end -= 1;
        }
        let upto = &self.text[..end];
        let line = upto.matches('\n').count() + 1;
        let column = upto.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
        JsonError { kind, line, column }
    }

    /// Only white space may follow the value.
    fn end(&mut self) -> Result<(), JsonError> {
        self.ws();
        if self.i < self.s.len() {
            return Err(self.err(JsonErrorKind::TrailingCharacters));
        }
        Ok(())
    }

    fn peek(&self) -> Option<u8> {
        self.s.get(self.i).copied()
    }

    fn unexpected(&self) -> JsonError {
        match self.text[self.i.min(self.text.len())..].chars().next() {
            Some(c) => self.err(JsonErrorKind::UnexpectedChar(c)),
            None => self.err(JsonErrorKind::UnexpectedEnd),
        }
    }

    fn ws(&mut self) {
        while let Some(b' ' | b'\t' | b'\n' | b'\r') = self.peek() {
            self.i += 1;
        }
    }

    fn expect(&mut self, b: u8) -> Result<(), JsonError> {
        self.ws();
        if self.peek() == Some(b) {
            self.i += 1;
            Ok(())
        } else {
            Err(self.unexpected())
        }
    }

    /// One value, iteratively: containers go on an explicit stack.
    fn value(&mut self) -> Result<Value, JsonError> {
        let mut stack: Vec<Open> = Vec::new();
        loop {
            self.ws();
            // Read a scalar or open a container.
            let mut done = match self.peek() {
                Some(b'[') => {
                    self.i += 1;
                    self.ws();
                    if self.peek() == Some(b']') {
                        self.i += 1;
                        Some(Value::Array(Vec::new()))
                    } else {
                        stack.push(Open::Array(Vec::new()));
                        None
                    }
                }
                Some(b'{') => {
                    self.i += 1;
                    self.ws();
                    if self.peek() == Some(b'}') {
                        self.i += 1;
                        Some(Value::Object(Vec::new()))
                    } else {
                        let key = self.key()?;
                        stack.push(Open::Object(Vec::new(), key));
                        None
                    }
                }
                _ => Some(self.scalar()?),
            };
            if stack.len() > MAX_DEPTH {
                return Err(self.err(JsonErrorKind::TooDeep));
            }
            // Close every container the value completes.
            while let Some(v) = done.take() {
                let Some(top) = stack.last_mut() else {
                    return Ok(v);
                };
                self.ws();
                let next = self.peek();
                match top {
                    Open::Array(items) => {
                        items.push(v);
                        match next {
                            Some(b',') => self.i += 1,
                            Some(b']') => {
                                self.i += 1;
                                if let Some(Open::Array(items)) = stack.pop() {
                                    done = Some(Value::Array(items));
                                }
                            }
                            _ => return Err(self.unexpected()),
                        }
                    }
                    Open::Object(fields, key) => {
                        let key = std::mem::take(key);
                        if fields.iter().any(|(k, _)| *k == key) {
                            return Err(self.err(JsonErrorKind::DuplicateKey(key)));
                        }
                        fields.push((key, v));
                        match next {
                            Some(b',') => {
                                self.i += 1;
                                self.ws();
                                let k = self.key()?;
                                if let Some(Open::Object(_, slot)) = stack.last_mut() {
                                    *slot = k;
                                }
                            }
                            Some(b'}') => {
                                self.i += 1;
                                if let Some(Open::Object(fields, _)) = stack.pop() {
                                    done = Some(Value::Object(fields));
                                }
                            }
                            _ => return Err(self.unexpected()),
                        }
                    }
                }
            }
        }
    }

    /// `"key" :`
    fn key(&mut self) -> Result<String, JsonError> {
        self.ws();
        if self.peek() != Some(b'"') {
            return Err(self.unexpected());
        }
        let k = self.string()?;
        self.expect(b':')?;
        Ok(k)
    }

    fn scalar(&mut self) -> Result<Value, JsonError> {
        match self.peek() {
            Some(b'"') => Ok(Value::String(self.string()?)),
            Some(b'-' | b'0'..=b'9') => self.number(),
            Some(b't') => self.literal("true", Value::Bool(true)),
            Some(b'f') => self.literal("false", Value::Bool(false)),
            Some(b'n') => self.literal("null", Value::Null),
            _ => Err(self.unexpected()),
        }
    }

    fn literal(&mut self, word: &str, v: Value) -> Result<Value, JsonError> {
        if self.s[self.i..].starts_with(word.as_bytes()) {
            self.i += word.len();
            Ok(v)
        } else {
            Err(self.unexpected())
        }
    }

    fn digits(&mut self) -> usize {
        let start = self.i;
        while let Some(b'0'..=b'9') = self.peek() {
            self.i += 1;
        }
        self.i - start
    }

    fn number(&mut self) -> Result<Value, JsonError> {
        let start = self.i;
        if self.peek() == Some(b'-') {
            self.i += 1;
        }
        match self.peek() {
            Some(b'0') => self.i += 1,
            Some(b'1'..=b'9') => {
                self.digits();
            }
            _ => return Err(self.err(JsonErrorKind::BadNumber)),
        }
        if self.peek() == Some(b'.') {
            self.i += 1;
            if self.digits() == 0 {
                return Err(self.err(JsonErrorKind::BadNumber));
            }
        }
        if let Some(b'e' | b'E') = self.peek() {
            self.i += 1;
            if let Some(b'+' | b'-') = self.peek() {
                self.i += 1;
            }
            if self.digits() == 0 {
                return Err(self.err(JsonErrorKind::BadNumber));
            }
        }
        Ok(Value::Number(self.text[start..self.i].to_owned()))
    }

    fn hex4(&mut self) -> Result<u32, JsonError> {
        // Four hex digits exactly (`from_str_radix` alone would take a
        // sign: `\u+FFF`).
        let h = self
            .s
            .get(self.i..self.i + 4)
            .filter(|h| h.iter().all(u8::is_ascii_hexdigit))
            .and_then(|h| std::str::from_utf8(h).ok())
            .and_then(|h| u32::from_str_radix(h, 16).ok())
            .ok_or_else(|| self.err(JsonErrorKind::BadString))?;
        self.i += 4;
        Ok(h)
    }

    fn string(&mut self) -> Result<String, JsonError> {
        self.i += 1; // opening quote
        let mut out = String::new();
        loop {
            let start = self.i;
            while let Some(b) = self.peek() {
                if b == b'"' || b == b'\\' || b < 0x20 {
                    break;
                }
                self.i += 1;
            }
            out.push_str(&self.text[start..self.i]);
            match self.peek() {
                None => return Err(self.err(JsonErrorKind::UnexpectedEnd)),
                Some(b'"') => {
                    self.i += 1;
                    return Ok(out);
                }
                Some(b'\\') => {
                    self.i += 1;
                    let c = self
                        .peek()
                        .ok_or_else(|| self.err(JsonErrorKind::UnexpectedEnd))?;
                    self.i += 1;
                    match c {
                        b'"' => out.push('"'),
                        b'\\' => out.push('\\'),
                        b'/' => out.push('/'),
                        b'b' => out.push('\u{8}'),
                        b'f' => out.push('\u{c}'),
                        b'n' => out.push('\n'),
                        b'r' => out.push('\r'),
                        b't' => out.push('\t'),
                        b'u' => {
                            let hi = self.hex4()?;
                            let code = if (0xD800..0xDC00).contains(&hi) {
                                if !self.s[self.i..].starts_with(b"\\u") {
                                    return Err(self.err(JsonErrorKind::BadString));
                                }
                                self.i += 2;
                                let lo = self.hex4()?;
                                if !(0xDC00..0xE000).contains(&lo) {
                                    return Err(self.err(JsonErrorKind::BadString));
                                }
                                0x10000 + ((hi - 0xD800) << 10) + (lo - 0xDC00)
                            } else {
                                hi
                            };
                            out.push(
                                char::from_u32(code)
                                    .ok_or_else(|| self.err(JsonErrorKind::BadString))?,
                            );
                        }
                        _ => return Err(self.err(JsonErrorKind::BadString)),
                    }
                }
                Some(_) => return Err(self.err(JsonErrorKind::BadString)),
            }
        }
    }
}

impl Value {
    /// The value of `key` in an object.
    pub fn get(&self, key: &str) -> Option<&Value> {
        match self {
            Value::Object(fields) => fields.iter().find(|(k, _)| k == key).map(|(_, v)| v),
            _ => None,
        }
    }

    /// The value of `key` in an object, mutably.
    pub fn get_mut(&mut self, key: &str) -> Option<&mut Value> {
        match self {
            Value::Object(fields) => fields.iter_mut().find(|(k, _)| k == key).map(|(_, v)| v),
            _ => None,
        }
    }

    /// Removes `key` from an object, returning its value.
    pub fn remove(&mut self, key: &str) -> Option<Value> {
        match self {
            Value::Object(fields) => {
                let i = fields.iter().position(|(k, _)| k == key)?;
                Some(fields.remove(i).1)
            }
            _ => None,
        }
    }

    /// Sets `key` in an object (replacing or appending).
    pub fn set(&mut self, key: &str, v: Value) {
        if let Value::Object(fields) = self {
            match fields.iter_mut().find(|(k, _)| k == key) {
                Some((_, slot)) => *slot = v,
                None => fields.push((key.to_owned(), v)),
            }
        }
    }

    /// The items of an array.
    pub fn as_array(&self) -> Option<&Vec<Value>> {
        match self {
            Value::Array(items) => Some(items),
            _ => None,
        }
    }

    /// The items of an array, mutably.
    pub fn as_array_mut(&mut self) -> Option<&mut Vec<Value>> {
        match self {
            Value::Array(items) => Some(items),
            _ => None,
        }
    }

    /// The text of a string.
    pub fn as_str(&self) -> Option<&str> {
        match self {
            Value::String(s) => Some(s),
            _ => None,
        }
    }

    /// The text of a number.
    pub fn as_number(&self) -> Option<&str> {
        match self {
            Value::Number(s) => Some(s),
            _ => None,
        }
    }

    /// The compact JSON text of the value (numbers exactly as stored).
    pub fn to_json(&self) -> String {
        let mut out = String::new();
        self.write(&mut out);
        out
    }

    fn write(&self, out: &mut String) {
        match self {
            Value::Null => out.push_str("null"),
            Value::Bool(b) => out.push_str(if *b { "true" } else { "false" }),
            Value::Number(n) => out.push_str(n),
            Value::String(s) => write_string(out, s),
            Value::Array(items) => {
                out.push('[');
                for (i, v) in items.iter().enumerate() {
                    if i > 0 {
                        out.push(',');
                    }
                    v.write(out);
                }
                out.push(']');
            }
            Value::Object(fields) => {
                out.push('{');
                for (i, (k, v)) in fields.iter().enumerate() {
                    if i > 0 {
                        out.push(',');
                    }
                    write_string(out, k);
                    out.push(':');
                    v.write(out);
                }
                out.push('}');
            }
        }
    }
}

fn write_string(out: &mut String, s: &str) {
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            '\t' => out.push_str("\\t"),
            c if (c as u32) < 0x20 => {
                let _ = write!(out, "\\u{:04x}", c as u32);
            }
            c => out.push(c),
        }
    }
    out.push('"');
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_keep_their_text() {
        let v = parse("[0.30000000000000004, -0.0, 1e-7, 12E+3]").unwrap();
        let texts: Vec<&str> = v
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_number().unwrap())
            .collect();
        assert_eq!(texts, ["0.30000000000000004", "-0.0", "1e-7", "12E+3"]);
    }

    #[test]
    fn round_trip_is_exact() {
        let text = r#"{"a":[1,2.5,{"b":null,"c":true}],"s":"x\"y\\z\n\u0001é"}"#;
        let v = parse(text).unwrap();
        assert_eq!(parse(&v.to_json()).unwrap(), v);
        assert_eq!(v.get("s").unwrap().as_str().unwrap(), "x\"y\\z\n\u{1}é");
    }

    #[test]
    fn syntax_errors_say_where() {
        let e = parse("{\n  \"a\": [1, 2,, 3]\n}").unwrap_err();
        assert_eq!((e.line, e.column), (2, 14));
        assert!(matches!(e.kind, JsonErrorKind::UnexpectedChar(',')));
        for bad in [
            "",
            "[",
            "01",
            "1.",
            "-",
            "1e",
            "[1] 2",
            "{\"a\" 1}",
            "\"\\x\"",
            "tru",
            "{1: 2}",
            "[1,]",
            "\"a\nb\"",
            "\"\\ud800\"",
            "\"\\u+FFF\"",
            "\"\\u-001\"",
        ] {
            assert!(parse(bad).is_err(), "{bad:?} must be rejected");
        }
        assert!(matches!(
            parse("{\"k\": 1, \"k\": 2}").unwrap_err().kind,
            JsonErrorKind::DuplicateKey(_)
        ));
    }

    #[test]
    fn an_escape_of_a_multibyte_character_is_an_error_at_that_character() {
        // Found by fuzzing `verify`: the error's position was sliced inside
        // the character and panicked.
        for (text, column) in [("\"ab\\\u{186}\"", 5), ("{\"fes\\\u{1F600}x\": 1}", 7)] {
            let e = parse(text).unwrap_err();
            assert!(matches!(e.kind, JsonErrorKind::BadString), "{text:?}");
            assert_eq!((e.line, e.column), (1, column), "{text:?}");
        }
    }

    #[test]
    fn streaming_hands_over_each_element_and_keeps_the_rest() {
        let text = r#"{"a": 1, "levels": [{"z": "1"}, [2], 3], "b": [4]}"#;
        let mut seen = Vec::new();
        let rest = parse_streaming(text, "levels", |i, v| {
            seen.push((i, v.to_json()));
            Ok::<(), JsonError>(())
        })
        .unwrap();
        assert_eq!(
            seen,
            [
                (0, r#"{"z":"1"}"#.into()),
                (1, "[2]".into()),
                (2, "3".into())
            ]
        );
        assert_eq!(rest.to_json(), r#"{"a":1,"levels":[],"b":[4]}"#);
        let all = parse(text).unwrap();
        let mut again = Vec::new();
        parse_streaming(text, "none", |_, v| {
            again.push(v);
            Ok::<(), JsonError>(())
        })
        .map(|v| assert_eq!(v, all))
        .unwrap();
        assert!(again.is_empty());
        for bad in [
            r#"{"levels": [1,]}"#,
            r#"{"levels": [1] "#,
            r#"{"levels": [] } x"#,
        ] {
            assert!(parse_streaming(bad, "levels", |_, _| Ok::<(), JsonError>(())).is_err());
        }
    }

    #[test]
    fn deep_nesting_is_an_error_not_a_stack_overflow() {
        let deep = format!("{}{}", "[".repeat(100_000), "]".repeat(100_000));
        assert_eq!(parse(&deep).unwrap_err().kind, JsonErrorKind::TooDeep);
        let ok = format!("{}{}", "[".repeat(MAX_DEPTH), "]".repeat(MAX_DEPTH));
        assert!(parse(&ok).is_ok());
    }
}

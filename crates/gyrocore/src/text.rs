//! Delimited text logs: the data rows of a CSV/TSV/whitespace file parsed straight into the
//! caller's `(rows, k)` float64 array (and the timestamps into their own `i64`/`f64` column),
//! in parallel over newline-aligned pieces.
//!
//! The grammar is exactly the one `numpy.loadtxt` reads, so that a file is either read with the
//! same values or refused at the same cell:
//!
//! ```text
//! line    = lines end at '\n' ("\r\n" too); a comment (the `comment` string) ends the line's
//!           content; a line whose content is empty is no row (loadtxt's rows are the others)
//! fields  = content split at the delimiter byte (empty fields kept), or at runs of spaces/tabs
//!           (whitespace mode: leading and trailing runs ignored, a line without fields is no row)
//! number  = [ \t]* [+-]? (digits [. digits*] | . digits) ([eE] [+-]? digits)? [ \t]*
//!           | [ \t]* [+-]? (nan | inf | infinity) [ \t]*       (case-insensitive)
//! integer = [ \t]* [+-]? digits [ \t]*                         (in i64; the stamps of an integer time column)
//! ```
//!
//! Numbers are rounded correctly (Eisel–Lemire with a big-decimal fallback, the `fast-float2`
//! crate), the same doubles as Python's `float()` and loadtxt. The selected columns are read in
//! the given order; for each, a row with too few fields ([`Stop::TooFewFields`]) or a cell that
//! is not a number ([`Stop::BadCell`]) stops the parse at the first such place in the file, as
//! loadtxt does. Bytes loadtxt reads differently from a plain ASCII parser — non-ASCII text, a
//! double quote, a lone carriage return, control characters — stop it with
//! [`Stop::Unsupported`], so that the caller can read the file another way.

use rayon::prelude::*;

use crate::{Error, Result};

/// Pieces below this many bytes are not split further (thread start-up costs more).
const MIN_PIECE: usize = 1 << 16;

/// What the parser reads: the delimiter, the comment string and the selected columns.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Format {
    delimiter: Option<u8>,
    comment: Vec<u8>,
    usecols: Vec<usize>,
    stamps: bool,
}

impl Format {
    /// The format of a file whose fields are separated by `delimiter` (`None`: runs of spaces
    /// and tabs), where `comment` (empty: none) starts a comment, and whose columns `usecols`
    /// (0-based file columns) are read in this order. With `stamps`, the first of them is the
    /// time column, written to its own output.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for a delimiter other than `,` `;` tab `|` `:`, a comment
    /// that is not printable ASCII or starts with the delimiter or a blank, no columns, or a
    /// column listed twice.
    pub fn new(
        delimiter: Option<u8>,
        comment: &[u8],
        usecols: &[usize],
        stamps: bool,
    ) -> Result<Self> {
        if let Some(d) = delimiter {
            if !matches!(d, b',' | b';' | b'\t' | b'|' | b':') {
                return Err(Error::invalid(
                    "delimiter",
                    format!("must be one of , ; tab | :, got byte {d}"),
                ));
            }
        }
        if comment.iter().any(|&c| !(0x21..0x7f).contains(&c))
            || comment.first().is_some_and(|&c| Some(c) == delimiter)
        {
            return Err(Error::invalid(
                "comment",
                "must be printable ASCII without blanks, not starting with the delimiter",
            ));
        }
        if usecols.is_empty() {
            return Err(Error::invalid("usecols", "must list at least one column"));
        }
        let mut seen = usecols.to_vec();
        seen.sort_unstable();
        if seen.windows(2).any(|w| w[0] == w[1]) {
            return Err(Error::invalid("usecols", "must not list a column twice"));
        }
        Ok(Self {
            delimiter,
            comment: comment.to_vec(),
            usecols: usecols.to_vec(),
            stamps,
        })
    }

    /// Values per row in the samples array (the selected columns less the time column).
    pub fn width(&self) -> usize {
        self.usecols.len() - usize::from(self.stamps)
    }

    fn class_table(&self) -> [u8; 256] {
        let mut t = [NORMAL; 256];
        for (b, c) in t.iter_mut().enumerate() {
            if b >= 0x80
                || b == 0x7f
                || (b < 0x20 && b != usize::from(b'\t'))
                || b == usize::from(b'"')
            {
                *c = UNSUPPORTED;
            }
        }
        t[usize::from(b'\n')] = NEWLINE;
        t[usize::from(b'\r')] = CR;
        if let Some(d) = self.delimiter {
            t[usize::from(d)] = DELIM;
        } else {
            t[usize::from(b' ')] = DELIM;
            t[usize::from(b'\t')] = DELIM;
        }
        if let Some(&c) = self.comment.first() {
            t[usize::from(c)] = COMMENT;
        }
        t
    }
}

const NORMAL: u8 = 0;
const DELIM: u8 = 1;
const NEWLINE: u8 = 2;
const CR: u8 = 3;
const COMMENT: u8 = 4;
const UNSUPPORTED: u8 = 5;

/// Where the timestamps go: nowhere (no time column), or an `i64` / `f64` column.
#[derive(Debug)]
pub enum Stamps<'a> {
    /// The format has no time column.
    None,
    /// Integer stamps (exact epoch nanoseconds).
    Int(&'a mut [i64]),
    /// Floating-point stamps.
    Float(&'a mut [f64]),
}

impl Stamps<'_> {
    fn len(&self) -> Option<usize> {
        match self {
            Stamps::None => None,
            Stamps::Int(s) => Some(s.len()),
            Stamps::Float(s) => Some(s.len()),
        }
    }

    fn split_at_mut(&mut self, mid: usize) -> (Stamps<'_>, Stamps<'_>) {
        match self {
            Stamps::None => (Stamps::None, Stamps::None),
            Stamps::Int(s) => {
                let (a, b) = s.split_at_mut(mid);
                (Stamps::Int(a), Stamps::Int(b))
            }
            Stamps::Float(s) => {
                let (a, b) = s.split_at_mut(mid);
                (Stamps::Float(a), Stamps::Float(b))
            }
        }
    }

    fn copy_within(&mut self, src: std::ops::Range<usize>, dest: usize) {
        match self {
            Stamps::None => {}
            Stamps::Int(s) => s.copy_within(src, dest),
            Stamps::Float(s) => s.copy_within(src, dest),
        }
    }
}

/// Why the parse stopped.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Stop {
    /// Every line of the text was read.
    Done,
    /// The output arrays are full; `consumed` bytes (whole lines) were read.
    Full,
    /// Data row `row` (0-based, counted as loadtxt counts rows: lines with content) has a cell
    /// that is not a number in file column `column` (0-based); `text` is the raw field.
    BadCell {
        /// Data row.
        row: usize,
        /// 0-based file column.
        column: usize,
        /// The field as written (blanks included).
        text: String,
    },
    /// Data row `row` has only `fields` fields, fewer than a selected column needs.
    TooFewFields {
        /// Data row.
        row: usize,
        /// Fields the row has.
        fields: usize,
    },
    /// Data row `row` holds something this parser does not read as loadtxt does (`reason`).
    Unsupported {
        /// Data row (lines with content before it).
        row: usize,
        /// What was found.
        reason: &'static str,
    },
}

/// The outcome of [`parse_into`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Parsed {
    /// Rows written (all rows before the stop).
    pub rows: usize,
    /// Bytes of `text` read, up to the end of the last row written (meaningful for
    /// [`Stop::Done`] and [`Stop::Full`]: the caller continues from there).
    pub consumed: usize,
    /// Why the parse ended.
    pub stop: Stop,
}

/// Parses the lines of `text` (whole lines; the last one may lack its newline) into `values`
/// (row-major, [`Format::width`] values a row) and `stamps`, using up to
/// `rayon::current_num_threads()` threads on newline-aligned pieces.
///
/// At most `values.len() / width` rows are written; when the text has more, the parse stops
/// with [`Stop::Full`] after the last row that fits.
///
/// # Errors
/// [`Error::ShapeMismatch`] when `values` is not a whole number of rows, or `stamps` does not
/// match the format (a time column without a stamps array or the reverse, or fewer stamps
/// than rows).
pub fn parse_into(
    text: &[u8],
    format: &Format,
    values: &mut [f64],
    mut stamps: Stamps<'_>,
) -> Result<Parsed> {
    let k = format.width();
    if k == 0 {
        if !values.is_empty() {
            return Err(Error::ShapeMismatch {
                name: "values",
                reason: "the format has no sample columns".into(),
            });
        }
    } else if values.len() % k != 0 {
        return Err(Error::ShapeMismatch {
            name: "values",
            reason: format!("{} values are not whole rows of {k}", values.len()),
        });
    }
    let capacity = values.len().checked_div(k).unwrap_or(usize::MAX);
    let capacity = match (format.stamps, stamps.len()) {
        (false, None) => capacity,
        (true, Some(n)) => capacity.min(n),
        _ => {
            return Err(Error::ShapeMismatch {
                name: "stamps",
                reason: "given exactly when the format has a time column".into(),
            });
        }
    };
    let table = format.class_table();
    let threads = rayon::current_num_threads().clamp(1, 64);
    let pieces = split_lines(text, threads);
    let counts: Vec<usize> = pieces.iter().map(|&(a, b)| lines_in(&text[a..b])).collect();
    let total: usize = counts.iter().sum();
    if pieces.len() <= 1 || total > capacity {
        let (values, _) = values.split_at_mut(capacity.saturating_mul(k).min(values.len()));
        return Ok(parse_piece(
            text,
            format,
            &table,
            values,
            &mut stamps,
            capacity,
        ));
    }
    // Each piece writes from the row where it would start if every line were a row; pieces
    // with fewer rows (blank or comment lines) are closed up afterwards.
    let mut results: Vec<Parsed> = Vec::with_capacity(pieces.len());
    {
        let mut jobs = Vec::with_capacity(pieces.len());
        let mut rest_values: &mut [f64] = &mut *values;
        let mut rest_stamps = stamps.split_at_mut(0).1;
        for (&(a, b), &n) in pieces.iter().zip(&counts) {
            let (v, vr) = std::mem::take(&mut rest_values).split_at_mut(n * k);
            let (s, sr) = split_stamps(rest_stamps, n);
            rest_values = vr;
            rest_stamps = sr;
            jobs.push((&text[a..b], v, s, n));
        }
        jobs.into_par_iter()
            .map(|(piece, v, mut s, n)| parse_piece(piece, format, &table, v, &mut s, n))
            .collect_into_vec(&mut results);
    }
    let mut rows = 0;
    let mut start = 0; // first row slot of the current piece
    for (res, &n) in results.into_iter().zip(&counts) {
        if rows != start && res.rows > 0 {
            values.copy_within(start * k..(start + res.rows) * k, rows * k);
            stamps.copy_within(start..start + res.rows, rows);
        }
        let local = res.rows;
        match res.stop {
            Stop::Done => {}
            stop => {
                return Ok(Parsed {
                    rows: rows + local,
                    consumed: 0,
                    stop: offset_stop(stop, rows),
                });
            }
        }
        rows += local;
        start += n;
    }
    Ok(Parsed {
        rows,
        consumed: text.len(),
        stop: Stop::Done,
    })
}

fn split_stamps(s: Stamps<'_>, n: usize) -> (Stamps<'_>, Stamps<'_>) {
    match s {
        Stamps::None => (Stamps::None, Stamps::None),
        Stamps::Int(x) => {
            let (a, b) = x.split_at_mut(n);
            (Stamps::Int(a), Stamps::Int(b))
        }
        Stamps::Float(x) => {
            let (a, b) = x.split_at_mut(n);
            (Stamps::Float(a), Stamps::Float(b))
        }
    }
}

fn offset_stop(stop: Stop, rows: usize) -> Stop {
    match stop {
        Stop::BadCell { row, column, text } => Stop::BadCell {
            row: row + rows,
            column,
            text,
        },
        Stop::TooFewFields { row, fields } => Stop::TooFewFields {
            row: row + rows,
            fields,
        },
        Stop::Unsupported { row, reason } => Stop::Unsupported {
            row: row + rows,
            reason,
        },
        other => other,
    }
}

/// Lines in `text`: newlines, plus one for a last line without its newline (an upper bound
/// of its rows: the room [`parse_into`] needs to read it whole, in parallel).
pub fn lines_in(text: &[u8]) -> usize {
    memchr::memchr_iter(b'\n', text).count() + usize::from(text.last().is_some_and(|&b| b != b'\n'))
}

/// Up to `n` byte ranges covering `text`, each ending after a newline (the last at the end).
fn split_lines(text: &[u8], n: usize) -> Vec<(usize, usize)> {
    let n = n.min(text.len() / MIN_PIECE).max(1);
    let mut out = Vec::with_capacity(n);
    let mut start = 0;
    for i in 1..n {
        let target = (text.len() * i / n).max(start);
        let end = match memchr::memchr(b'\n', &text[target..]) {
            Some(j) => target + j + 1,
            None => text.len(),
        };
        if end > start {
            out.push((start, end));
            start = end;
        }
    }
    if start < text.len() || out.is_empty() {
        out.push((start, text.len()));
    }
    out
}

/// What one line gave.
enum Line {
    /// A row was written; the next line starts here.
    Row(usize),
    /// No row (blank or comment line); the next line starts here.
    Skip(usize),
    /// The parse stops here.
    Stop(Stop),
}

/// The parser's state for one piece: the format's tables and the row being written.
struct Piece<'a> {
    text: &'a [u8],
    format: &'a Format,
    table: &'a [u8; 256],
    /// `slot[c]`: where file column `c` goes (0 = the stamps when the format has them, then
    /// the values), `usize::MAX` when it is not read; up to the last read column.
    slot: Vec<usize>,
}

impl Piece<'_> {
    /// Writes value `slot` of row `row`.
    #[inline]
    fn store_float(
        &self,
        values: &mut [f64],
        stamps: &mut Stamps<'_>,
        row: usize,
        slot: usize,
        v: f64,
    ) {
        let k = self.format.width();
        if self.format.stamps {
            if slot == 0 {
                if let Stamps::Float(s) = stamps {
                    s[row] = v;
                }
            } else {
                values[row * k + slot - 1] = v;
            }
        } else {
            values[row * k + slot] = v;
        }
    }

    /// The common line, read in one pass: every field up to the last read column a plain
    /// number (or an unread field of plain bytes) right before the delimiter, nothing after
    /// the last read column. `None` when the line is anything else (the careful path reads it).
    #[inline]
    fn fast_line(
        &self,
        pos: usize,
        values: &mut [f64],
        stamps: &mut Stamps<'_>,
        row: usize,
    ) -> Option<usize> {
        let text = self.text;
        let n = text.len();
        let whitespace = self.format.delimiter.is_none();
        let last = self.slot.len() - 1;
        let int_stamps = matches!(stamps, Stamps::Int(_));
        let mut i = pos;
        for (col, &slot) in self.slot.iter().enumerate() {
            if whitespace {
                while i < n && (text[i] == b' ' || text[i] == b'\t') {
                    i += 1;
                }
            }
            if slot == usize::MAX {
                while i < n && self.table[usize::from(text[i])] == NORMAL {
                    i += 1;
                }
            } else if slot == 0 && int_stamps {
                let start = i;
                if i < n && (text[i] == b'-' || text[i] == b'+') {
                    i += 1;
                }
                while i < n && text[i].is_ascii_digit() {
                    i += 1;
                }
                let v = parse_int(&text[start..i])?;
                if let Stamps::Int(s) = stamps {
                    s[row] = v;
                }
            } else {
                let (v, used) = fast_float2::parse_partial::<f64, _>(&text[i..]).ok()?;
                i += used;
                self.store_float(values, stamps, row, slot, v);
            }
            if i >= n {
                return (col == last).then_some(n);
            }
            let b = text[i];
            if col < last {
                if self.table[usize::from(b)] != DELIM {
                    return None;
                }
                i += 1;
            } else if b == b'\n' {
                return Some(i + 1);
            } else if b == b'\r' && i + 1 < n && text[i + 1] == b'\n' {
                return Some(i + 2);
            } else {
                return None;
            }
        }
        None
    }

    /// Any line, as loadtxt reads it: the fields, the comment, blank lines, the checks in the
    /// order of the selected columns.
    fn careful_line(
        &self,
        pos: usize,
        values: &mut [f64],
        stamps: &mut Stamps<'_>,
        row: usize,
        capacity: usize,
        bounds: &mut Vec<(usize, usize)>,
    ) -> Line {
        let text = self.text;
        let table = self.table;
        let format = self.format;
        let whitespace = format.delimiter.is_none();
        let comment = format.comment.as_slice();
        let max_col = self.slot.len() - 1;
        let n = text.len();
        bounds.clear();
        let mut fields = 0usize;
        let mut field_start = pos;
        let mut in_field = !whitespace; // whitespace mode: between fields
        let mut content_end = None; // where a comment cut the line
        let mut bad: Option<&'static str> = None;
        let mut i = pos;
        let line_end;
        let next;
        loop {
            if i >= n {
                line_end = n;
                next = n;
                break;
            }
            let b = text[i];
            match table[usize::from(b)] {
                COMMENT if text[i..].starts_with(comment) => {
                    // the rest of the line is a comment: only its bytes are checked
                    let stop = memchr::memchr(b'\n', &text[i..]).map_or(n, |j| i + j);
                    let mut cr_end = stop;
                    if stop > i && text[stop - 1] == b'\r' {
                        cr_end = stop - 1;
                    }
                    if text[i..cr_end]
                        .iter()
                        .any(|&c| table[usize::from(c)] == UNSUPPORTED || c == b'\r')
                    {
                        bad.get_or_insert("a non-ASCII or control character in a comment");
                    }
                    content_end = Some(i);
                    line_end = cr_end;
                    next = if stop < n { stop + 1 } else { n };
                    break;
                }
                NORMAL | COMMENT => {
                    // (a comment byte that does not start the comment string is a plain byte)
                    if !in_field {
                        in_field = true;
                        field_start = i;
                    }
                }
                DELIM => {
                    if whitespace {
                        if in_field {
                            if fields <= max_col {
                                bounds.push((field_start, i));
                            }
                            fields += 1;
                            in_field = false;
                        }
                    } else {
                        if fields <= max_col {
                            bounds.push((field_start, i));
                        }
                        fields += 1;
                        field_start = i + 1;
                    }
                }
                NEWLINE => {
                    line_end = i;
                    next = i + 1;
                    break;
                }
                CR => {
                    if i + 1 < n && text[i + 1] == b'\n' {
                        line_end = i;
                        next = i + 2;
                        break;
                    }
                    bad.get_or_insert("a carriage return inside a line");
                }
                _ => {
                    bad.get_or_insert(if b == b'"' {
                        "a double quote"
                    } else {
                        "a non-ASCII or control character"
                    });
                    if !in_field {
                        in_field = true;
                        field_start = i;
                    }
                }
            }
            i += 1;
        }
        let end = content_end.unwrap_or(line_end);
        // the last field
        let empty = if whitespace {
            if in_field {
                if fields <= max_col {
                    bounds.push((field_start, end));
                }
                fields += 1;
            }
            fields == 0
        } else if end == pos {
            true
        } else {
            if fields <= max_col {
                bounds.push((field_start, end));
            }
            fields += 1;
            false
        };
        if let Some(reason) = bad {
            return Line::Stop(Stop::Unsupported { row, reason });
        }
        if empty {
            return Line::Skip(next); // no content: no row (loadtxt skips it too)
        }
        if row >= capacity {
            return Line::Stop(Stop::Full);
        }
        for &col in &format.usecols {
            if col >= fields {
                return Line::Stop(Stop::TooFewFields { row, fields });
            }
            let (a, b) = bounds[col];
            let cell = &text[a..b];
            let slot = self.slot[col];
            let ok = match stamps {
                Stamps::Int(s) if slot == 0 => parse_int(cell).map(|v| s[row] = v).is_some(),
                _ => parse_float(cell)
                    .map(|v| self.store_float(values, stamps, row, slot, v))
                    .is_some(),
            };
            if !ok {
                return Line::Stop(Stop::BadCell {
                    row,
                    column: col,
                    text: String::from_utf8_lossy(cell).into_owned(),
                });
            }
        }
        Line::Row(next)
    }
}

/// The sequential parser of one piece: at most `capacity` rows.
fn parse_piece(
    text: &[u8],
    format: &Format,
    table: &[u8; 256],
    values: &mut [f64],
    stamps: &mut Stamps<'_>,
    capacity: usize,
) -> Parsed {
    let max_col = format.usecols.iter().copied().max().unwrap_or(0);
    let mut slot = vec![usize::MAX; max_col + 1];
    for (j, &c) in format.usecols.iter().enumerate() {
        slot[c] = j;
    }
    let piece = Piece {
        text,
        format,
        table,
        slot,
    };
    let mut bounds: Vec<(usize, usize)> = Vec::with_capacity(max_col + 1);
    let mut pos = 0;
    let mut row = 0;
    while pos < text.len() {
        if row < capacity {
            if let Some(next) = piece.fast_line(pos, values, stamps, row) {
                pos = next;
                row += 1;
                continue;
            }
        }
        match piece.careful_line(pos, values, stamps, row, capacity, &mut bounds) {
            Line::Row(next) => {
                pos = next;
                row += 1;
            }
            Line::Skip(next) => pos = next,
            Line::Stop(stop) => return stopped(row, pos, stop),
        }
    }
    Parsed {
        rows: row,
        consumed: text.len(),
        stop: Stop::Done,
    }
}

fn stopped(rows: usize, consumed: usize, stop: Stop) -> Parsed {
    Parsed {
        rows,
        consumed,
        stop,
    }
}

/// `cell` without the spaces and tabs around it.
fn trim(cell: &[u8]) -> &[u8] {
    let start = cell
        .iter()
        .position(|&b| b != b' ' && b != b'\t')
        .unwrap_or(cell.len());
    let end = cell
        .iter()
        .rposition(|&b| b != b' ' && b != b'\t')
        .map_or(start, |e| e + 1);
    &cell[start..end]
}

/// A number as loadtxt reads it (see the module grammar), correctly rounded; `None` otherwise.
pub fn parse_float(cell: &[u8]) -> Option<f64> {
    let s = trim(cell);
    // fast-float2 reads exactly this grammar (the decimal forms, nan, inf, infinity with an
    // optional sign), and rejects trailing characters.
    fast_float2::parse::<f64, _>(s).ok()
}

/// An integer as loadtxt reads it into int64; `None` when not one (or out of range).
pub fn parse_int(cell: &[u8]) -> Option<i64> {
    let s = trim(cell);
    let (negative, digits) = match s.first()? {
        b'-' => (true, &s[1..]),
        b'+' => (false, &s[1..]),
        _ => (false, s),
    };
    if digits.is_empty() {
        return None;
    }
    let mut acc: i64 = 0;
    for &d in digits {
        if !d.is_ascii_digit() {
            return None;
        }
        let digit = i64::from(d - b'0');
        acc = acc.checked_mul(10)?;
        acc = if negative {
            acc.checked_sub(digit)?
        } else {
            acc.checked_add(digit)?
        };
    }
    Some(acc)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(text: &str, delim: Option<u8>, usecols: &[usize], stamps: bool) -> (Vec<f64>, Parsed) {
        let f = Format::new(delim, b"#", usecols, stamps).unwrap();
        let mut v = vec![f64::NAN; 64 * f.width()];
        let mut s = vec![0.0; 64];
        let st = if stamps {
            Stamps::Float(&mut s)
        } else {
            Stamps::None
        };
        let p = parse_into(text.as_bytes(), &f, &mut v, st).unwrap();
        v.truncate(p.rows * f.width());
        (v, p)
    }

    #[test]
    fn numbers_like_python_float() {
        for (s, want) in [
            ("1", 1.0),
            ("+1.5", 1.5),
            ("1.", 1.0),
            (".5", 0.5),
            (" 1e5 ", 1e5),
            ("-0", -0.0),
            ("1e-320", 1e-320),
            ("1.7976931348623157e308", f64::MAX),
            ("1e400", f64::INFINITY),
            ("-Infinity", f64::NEG_INFINITY),
        ] {
            let got = parse_float(s.as_bytes()).unwrap();
            assert_eq!(got.to_bits(), want.to_bits(), "{s}");
        }
        assert!(parse_float(b"NaN").unwrap().is_nan());
        for s in [
            "", " ", "1e", ".", "e5", "+-1", "1_0", "0x10", "nan(1)", "1d5", "1.5 x",
        ] {
            assert!(parse_float(s.as_bytes()).is_none(), "{s}");
        }
    }

    #[test]
    fn integers_in_i64() {
        assert_eq!(parse_int(b" +5 "), Some(5));
        assert_eq!(parse_int(b"-9223372036854775808"), Some(i64::MIN));
        assert_eq!(parse_int(b"9223372036854775808"), None);
        assert_eq!(parse_int(b"5.0"), None);
        assert_eq!(parse_int(b"-"), None);
    }

    #[test]
    fn rows_comments_and_blank_lines() {
        let (v, p) = run("1,2 # c\n\n# x\n3,4,5\r\n", Some(b','), &[0, 1], false);
        assert_eq!(p.stop, Stop::Done);
        assert_eq!(v, vec![1.0, 2.0, 3.0, 4.0]);
        // a blank-only line is a row (loadtxt), and its cell is not a number
        let (_, p) = run("1,2\n  \n3,4\n", Some(b','), &[0, 1], false);
        assert_eq!(
            p.stop,
            Stop::BadCell {
                row: 1,
                column: 0,
                text: "  ".into()
            }
        );
        // the columns are checked in the given order
        let (_, p) = run("1,2\nx\n", Some(b','), &[1, 0], false);
        assert_eq!(p.stop, Stop::TooFewFields { row: 1, fields: 1 });
        let (_, p) = run("1,2\nx\n", Some(b','), &[0, 1], false);
        assert!(matches!(
            p.stop,
            Stop::BadCell {
                row: 1,
                column: 0,
                ..
            }
        ));
        let (v, p) = run(" 1  2\n\n   \n3\t4 \n", None, &[1, 0], true);
        assert_eq!(p.stop, Stop::Done);
        assert_eq!((v, p.rows), (vec![1.0, 3.0], 2));
        let (_, p) = run("1,\"2\"\n", Some(b','), &[0, 1], false);
        assert!(matches!(p.stop, Stop::Unsupported { .. }));
        let (_, p) = run("1,2\r3,4\n", Some(b','), &[0, 1], false);
        assert!(matches!(p.stop, Stop::Unsupported { .. }));
    }

    #[test]
    fn parallel_pieces_close_up_and_report_the_first_error() {
        use std::fmt::Write;
        let mut text = String::new();
        for i in 0..40_000 {
            writeln!(text, "{i},{}.25", i * 2).unwrap();
            if i % 1000 == 7 {
                text.push_str("# comment\n\n");
            }
        }
        let f = Format::new(Some(b','), b"#", &[0, 1], true).unwrap();
        let mut v = vec![0.0; 50_000];
        let mut s = vec![0i64; 50_000];
        let p = parse_into(text.as_bytes(), &f, &mut v, Stamps::Int(&mut s)).unwrap();
        assert_eq!(p.rows, 40_000);
        for i in 0..40_000 {
            assert_eq!(s[i], i as i64);
            assert_eq!(v[i], (i * 2) as f64 + 0.25);
        }
        let bad = text.replacen("39990,79980.25", "39990,x", 1);
        let bad = bad.replacen("30000,60000.25", "30000", 1);
        let p = parse_into(bad.as_bytes(), &f, &mut v, Stamps::Int(&mut s)).unwrap();
        assert_eq!(
            p.stop,
            Stop::TooFewFields {
                row: 30_000,
                fields: 1
            }
        );
        // output too small: stops at a whole row, and resumes there
        let mut small = vec![0.0; 100];
        let mut ss = vec![0i64; 100];
        let p = parse_into(text.as_bytes(), &f, &mut small, Stamps::Int(&mut ss)).unwrap();
        assert_eq!((p.rows, p.stop.clone()), (100, Stop::Full));
        assert!(text[p.consumed..].starts_with("100,200.25\n"));
    }

    #[test]
    fn bad_formats_are_errors() {
        assert!(Format::new(Some(b'.'), b"#", &[0], false).is_err());
        assert!(Format::new(Some(b','), b",", &[0], false).is_err());
        assert!(Format::new(Some(b','), b"#", &[], false).is_err());
        assert!(Format::new(Some(b','), b"#", &[1, 1], false).is_err());
        let f = Format::new(Some(b','), b"#", &[0, 1], true).unwrap();
        let mut v = vec![0.0; 3];
        assert!(parse_into(b"1,2\n", &f, &mut v, Stamps::None).is_err());
    }
}

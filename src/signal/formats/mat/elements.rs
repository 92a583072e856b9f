//! MAT-file level 5 data elements: the 8-byte tag (or the 4-byte small-element tag), typed
//! numeric data, `miMATRIX` arrays (numeric, struct) and `miCOMPRESSED` (zlib) blocks.
//! Layout from MathWorks, "MAT-File Format", R2024a, chapter 1.

/// Data types of a data element tag.
const MI_INT8: u32 = 1;
const MI_UINT8: u32 = 2;
const MI_INT16: u32 = 3;
const MI_UINT16: u32 = 4;
const MI_INT32: u32 = 5;
const MI_UINT32: u32 = 6;
const MI_SINGLE: u32 = 7;
const MI_DOUBLE: u32 = 9;
const MI_INT64: u32 = 12;
const MI_UINT64: u32 = 13;
const MI_MATRIX: u32 = 14;
const MI_COMPRESSED: u32 = 15;

/// Array classes (array flags, low byte).
const MX_STRUCT: u8 = 2;
const MX_DOUBLE: u8 = 6;
const MX_UINT64: u8 = 15;

/// Largest size a compressed variable may inflate to (a corrupt or hostile stream would
/// otherwise ask for unbounded memory).
const MAX_INFLATED: usize = 1 << 32;

/// One variable (or struct field) of a MAT-file.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    /// A real numeric array, column-major, with its dimensions.
    Numeric { dims: Vec<usize>, data: Vec<f64> },
    /// A 1x1 struct: its fields in file order.
    Struct(Vec<(String, Value)>),
    /// Anything else (char, cell, complex, sparse, struct array, object): what it is.
    Other(String),
}

/// A reader over one byte block, in the file's byte order.
pub struct Reader<'a> {
    bytes: &'a [u8],
    pos: usize,
    big_endian: bool,
}

impl<'a> Reader<'a> {
    pub fn new(bytes: &'a [u8], big_endian: bool) -> Reader<'a> {
        Reader {
            bytes,
            pos: 0,
            big_endian,
        }
    }

    pub fn at_end(&self) -> bool {
        self.pos >= self.bytes.len()
    }

    fn u32_at(&self, at: usize) -> Result<u32, String> {
        let b: [u8; 4] = self
            .bytes
            .get(at..at + 4)
            .and_then(|s| s.try_into().ok())
            .ok_or("the file ends inside a data element tag")?;
        Ok(if self.big_endian {
            u32::from_be_bytes(b)
        } else {
            u32::from_le_bytes(b)
        })
    }

    /// The next data element: its type and its bytes (padding skipped).
    pub fn element(&mut self) -> Result<(u32, &'a [u8]), String> {
        let first = self.u32_at(self.pos)?;
        if first >> 16 != 0 {
            // Small data element: size and type packed in 4 bytes, data in the next 4.
            let (ty, size) = (first & 0xffff, (first >> 16) as usize);
            if size > 4 {
                return Err(format!("small data element of {size} bytes (at most 4)"));
            }
            let data = self
                .bytes
                .get(self.pos + 4..self.pos + 4 + size)
                .ok_or("the file ends inside a small data element")?;
            self.pos += 8;
            return Ok((ty, data));
        }
        let size = self.u32_at(self.pos + 4)? as usize;
        let start = self.pos + 8;
        let data = start
            .checked_add(size)
            .and_then(|end| self.bytes.get(start..end))
            .ok_or_else(|| {
                format!("a data element announces {size} bytes past the end of the file")
            })?;
        // Compressed elements are not padded; the others end on an 8-byte boundary.
        let padded = if first == MI_COMPRESSED {
            size
        } else {
            size.div_ceil(8) * 8
        };
        self.pos = start.saturating_add(padded);
        Ok((first, data))
    }

    /// The next variable at the top level: name and value (`None` for a non-matrix element).
    pub fn variable(&mut self) -> Result<Option<(String, Value)>, String> {
        let (ty, data) = self.element()?;
        match ty {
            MI_COMPRESSED => {
                let inflated =
                    miniz_oxide::inflate::decompress_to_vec_zlib_with_limit(data, MAX_INFLATED)
                        .map_err(|e| {
                            format!(
                                "a compressed variable does not inflate (zlib: {:?})",
                                e.status
                            )
                        })?;
                let mut inner = Reader::new(&inflated, self.big_endian);
                inner.variable()
            }
            MI_MATRIX => matrix(data, self.big_endian).map(Some),
            _ => Ok(None),
        }
    }
}

/// Numbers of a numeric data element of type `ty`, as f64.
fn numbers(ty: u32, data: &[u8], big: bool) -> Result<Vec<f64>, String> {
    macro_rules! conv {
        ($t:ty, $n:expr) => {
            data.chunks_exact($n)
                .map(|c| {
                    let b = c.try_into().unwrap_or([0; $n]);
                    (if big {
                        <$t>::from_be_bytes(b)
                    } else {
                        <$t>::from_le_bytes(b)
                    }) as f64
                })
                .collect()
        };
    }
    Ok(match ty {
        MI_INT8 => data.iter().map(|&b| b as i8 as f64).collect(),
        MI_UINT8 => data.iter().map(|&b| b as f64).collect(),
        MI_INT16 => conv!(i16, 2),
        MI_UINT16 => conv!(u16, 2),
        MI_INT32 => conv!(i32, 4),
        MI_UINT32 => conv!(u32, 4),
        MI_SINGLE => conv!(f32, 4),
        MI_DOUBLE => conv!(f64, 8),
        MI_INT64 => conv!(i64, 8),
        MI_UINT64 => conv!(u64, 8),
        other => return Err(format!("numeric data of element type {other}")),
    })
}

fn class_name(class: u8) -> &'static str {
    match class {
        1 => "cell array",
        2 => "struct",
        3 => "object",
        4 => "char array",
        5 => "sparse array",
        16 => "function handle",
        17 => "opaque object (string, table, datetime)",
        _ => "array of an unknown class",
    }
}

/// An `miMATRIX` element: array flags, dimensions, name, then the class's content.
fn matrix(data: &[u8], big: bool) -> Result<(String, Value), String> {
    let mut r = Reader::new(data, big);
    if data.is_empty() {
        // An empty matrix element (an empty struct field).
        return Ok((String::new(), Value::Other("empty array".into())));
    }
    let (_, flags) = r.element()?;
    let flag_word = numbers(
        MI_UINT32,
        flags.get(..4).ok_or("array flags too short")?,
        big,
    )?[0] as u32;
    let class = (flag_word & 0xff) as u8;
    let complex = flag_word & 0x0800 != 0;
    let (dty, dims) = r.element()?;
    let dims: Vec<usize> = numbers(dty, dims, big)?
        .into_iter()
        .map(|d| if d >= 0.0 { d as usize } else { 0 })
        .collect();
    let (_, name) = r.element()?;
    let name = String::from_utf8_lossy(name).into_owned();
    let count = dims
        .iter()
        .try_fold(1usize, |a, &d| a.checked_mul(d))
        .ok_or("dimensions overflow")?;
    let value = match class {
        MX_DOUBLE..=MX_UINT64 if complex => Value::Other("complex array".into()),
        MX_DOUBLE..=MX_UINT64 => {
            let (ty, re) = r.element()?;
            let data = numbers(ty, re, big)?;
            if data.len() != count {
                return Err(format!(
                    "variable `{name}`: dimensions {dims:?} announce {count} values, the data holds {}",
                    data.len()
                ));
            }
            Value::Numeric { dims, data }
        }
        MX_STRUCT if count == 1 => Value::Struct(struct_fields(&mut r, big)?),
        MX_STRUCT => Value::Other(format!("struct array of {count} elements")),
        other => Value::Other(class_name(other).into()),
    };
    Ok((name, value))
}

/// The fields of a 1x1 struct: field-name length, the names, then one matrix per field.
fn struct_fields(r: &mut Reader, big: bool) -> Result<Vec<(String, Value)>, String> {
    let (ty, len) = r.element()?;
    let len = *numbers(ty, len, big)?
        .first()
        .ok_or("struct without a field-name length")? as usize;
    let (_, names) = r.element()?;
    if len == 0 {
        return Ok(Vec::new());
    }
    let mut fields = Vec::new();
    for chunk in names.chunks(len) {
        let end = chunk.iter().position(|&b| b == 0).unwrap_or(chunk.len());
        let field = String::from_utf8_lossy(&chunk[..end]).into_owned();
        let (ty, data) = r.element()?;
        if ty != MI_MATRIX {
            return Err(format!(
                "struct field `{field}` is element type {ty}, not a matrix"
            ));
        }
        let (_, value) = matrix(data, big)?;
        fields.push((field, value));
    }
    Ok(fields)
}

//! TDMS data types, property values and a bounds-checked cursor over the file's bytes, in the
//! segment's byte order. Type codes from NI, "TDMS File Format Internal Structure" (tdsDataType).

/// A TDMS data type, as the raw data index and the properties give it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DataType {
    I8,
    I16,
    I32,
    I64,
    U8,
    U16,
    U32,
    U64,
    F32,
    F64,
    Text,
    Bool,
    Timestamp,
    ComplexF32,
    ComplexF64,
    DaqmxRaw,
    Other(u32),
}

impl DataType {
    pub fn from_code(code: u32) -> DataType {
        match code {
            1 => DataType::I8,
            2 => DataType::I16,
            3 => DataType::I32,
            4 => DataType::I64,
            5 => DataType::U8,
            6 => DataType::U16,
            7 => DataType::U32,
            8 => DataType::U64,
            // 0x19 and 0x1A are "float with unit": stored as plain floats.
            9 | 0x19 => DataType::F32,
            10 | 0x1A => DataType::F64,
            0x20 => DataType::Text,
            0x21 => DataType::Bool,
            0x44 => DataType::Timestamp,
            0x0008_000C => DataType::ComplexF32,
            0x0010_000D => DataType::ComplexF64,
            0xFFFF_FFFF => DataType::DaqmxRaw,
            other => DataType::Other(other),
        }
    }

    /// Bytes per value; `None` for strings (their size is in the raw data index) and for
    /// types of unknown size.
    pub fn size(self) -> Option<usize> {
        match self {
            DataType::I8 | DataType::U8 | DataType::Bool => Some(1),
            DataType::I16 | DataType::U16 => Some(2),
            DataType::I32 | DataType::U32 | DataType::F32 => Some(4),
            DataType::I64 | DataType::U64 | DataType::F64 | DataType::ComplexF32 => Some(8),
            DataType::Timestamp | DataType::ComplexF64 => Some(16),
            DataType::Text | DataType::DaqmxRaw | DataType::Other(_) => None,
        }
    }

    /// A real number per value (read as a channel).
    pub fn is_real(self) -> bool {
        !matches!(
            self,
            DataType::Text
                | DataType::Bool
                | DataType::Timestamp
                | DataType::ComplexF32
                | DataType::ComplexF64
                | DataType::DaqmxRaw
                | DataType::Other(_)
        )
    }

    pub fn describe(self) -> String {
        match self {
            DataType::Text => "strings".into(),
            DataType::Bool => "booleans".into(),
            DataType::Timestamp => "timestamps".into(),
            DataType::ComplexF32 | DataType::ComplexF64 => "complex values".into(),
            DataType::DaqmxRaw => "DAQmx raw data".into(),
            DataType::Other(code) => format!("data type 0x{code:x}"),
            real => format!("{real:?}").to_lowercase(),
        }
    }
}

/// A real value of a numeric type from its bytes (exactly `size()` of them).
pub fn real_value(dt: DataType, b: &[u8], big: bool) -> f64 {
    macro_rules! num {
        ($t:ty) => {{
            let a = b.try_into().unwrap_or_default();
            (if big {
                <$t>::from_be_bytes(a)
            } else {
                <$t>::from_le_bytes(a)
            }) as f64
        }};
    }
    match dt {
        DataType::I8 => num!(i8),
        DataType::I16 => num!(i16),
        DataType::I32 => num!(i32),
        DataType::I64 => num!(i64),
        DataType::U8 => num!(u8),
        DataType::U16 => num!(u16),
        DataType::U32 => num!(u32),
        DataType::U64 => num!(u64),
        DataType::F32 => num!(f32),
        DataType::F64 => num!(f64),
        _ => f64::NAN,
    }
}

/// A timestamp (seconds since 1904-01-01 UTC and a binary fraction of a second) as one number
/// in units of 2^-64 s, so that differences between samples keep every bit.
pub fn timestamp_ticks(b: &[u8], big: bool) -> i128 {
    let (secs, frac) = if big {
        (&b[0..8], &b[8..16])
    } else {
        (&b[8..16], &b[0..8])
    };
    let s = real_value(DataType::I64, secs, big) as i128;
    let mut f = [0u8; 8];
    f.copy_from_slice(frac);
    let f = if big {
        u64::from_be_bytes(f)
    } else {
        u64::from_le_bytes(f)
    };
    (s << 64) + f as i128
}

/// A property's value: a number (any real type), a string, or something else.
#[derive(Debug, Clone, PartialEq)]
pub enum PropValue {
    Number(f64),
    Text(String),
    Other,
}

/// A cursor over the file's bytes in one segment's byte order; every read is bounds-checked
/// and a short read is an error naming the byte.
pub struct Cursor<'a> {
    bytes: &'a [u8],
    pub pos: usize,
    /// Reads stop here (the end of the metadata or of the segment).
    pub end: usize,
    pub big: bool,
}

impl<'a> Cursor<'a> {
    pub fn new(bytes: &'a [u8], pos: usize, end: usize, big: bool) -> Cursor<'a> {
        Cursor {
            bytes,
            pos,
            end: end.min(bytes.len()),
            big,
        }
    }

    pub fn take(&mut self, n: usize) -> Result<&'a [u8], String> {
        match self.pos.checked_add(n) {
            Some(stop) if stop <= self.end => {
                let b = &self.bytes[self.pos..stop];
                self.pos = stop;
                Ok(b)
            }
            _ => Err(format!(
                "{n} bytes needed at byte {}, but the block ends at byte {}",
                self.pos, self.end
            )),
        }
    }

    pub fn u32(&mut self) -> Result<u32, String> {
        let b: [u8; 4] = self.take(4)?.try_into().unwrap_or_default();
        Ok(if self.big {
            u32::from_be_bytes(b)
        } else {
            u32::from_le_bytes(b)
        })
    }

    pub fn u64(&mut self) -> Result<u64, String> {
        let b: [u8; 8] = self.take(8)?.try_into().unwrap_or_default();
        Ok(if self.big {
            u64::from_be_bytes(b)
        } else {
            u64::from_le_bytes(b)
        })
    }

    /// A length-prefixed UTF-8 string (invalid bytes replaced).
    pub fn string(&mut self) -> Result<String, String> {
        let n = self.u32()? as usize;
        Ok(String::from_utf8_lossy(self.take(n)?).into_owned())
    }

    /// The start of every raw data index: the data type, the array dimension (1: TDMS has
    /// no other) and the number of values per chunk.
    pub fn index_head(&mut self, path: &str) -> Result<(DataType, u64), String> {
        let data_type = DataType::from_code(self.u32()?);
        let dimension = self.u32()?;
        if dimension != 1 {
            return Err(format!(
                "object `{path}` has array dimension {dimension}; TDMS allows only 1"
            ));
        }
        Ok((data_type, self.u64()?))
    }

    /// One property: its name, type code and value.
    pub fn property(&mut self) -> Result<(String, PropValue), String> {
        let name = self.string()?;
        let dt = DataType::from_code(self.u32()?);
        let value = match dt {
            DataType::Text => PropValue::Text(self.string()?),
            real if real.is_real() => {
                let size = real.size().unwrap_or(0);
                PropValue::Number(real_value(real, self.take(size)?, self.big))
            }
            other => match other.size() {
                Some(size) => {
                    self.take(size)?;
                    PropValue::Other
                }
                None => {
                    return Err(format!(
                        "property `{name}` has {}, whose size is unknown",
                        other.describe()
                    ));
                }
            },
        };
        Ok((name, value))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_decode_in_either_byte_order() {
        let le = 0x0102_i16.to_le_bytes();
        let be = 0x0102_i16.to_be_bytes();
        assert_eq!(real_value(DataType::I16, &le, false), 258.0);
        assert_eq!(real_value(DataType::I16, &be, true), 258.0);
        assert_eq!(real_value(DataType::F32, &1.5f32.to_be_bytes(), true), 1.5);
    }

    #[test]
    fn a_short_read_names_the_byte() {
        let b = [1u8, 0, 0];
        let mut c = Cursor::new(&b, 0, 3, false);
        let e = c.u32().unwrap_err();
        assert!(e.contains("4 bytes needed at byte 0"), "{e}");
    }

    #[test]
    fn timestamps_keep_sub_nanosecond_differences() {
        // 1 s and 2^-64 s later (LE: fraction first, then seconds).
        let mut a = [0u8; 16];
        a[8..16].copy_from_slice(&5i64.to_le_bytes());
        let mut b = a;
        b[0..8].copy_from_slice(&1u64.to_le_bytes());
        assert_eq!(timestamp_ticks(&b, false) - timestamp_ticks(&a, false), 1);
    }
}

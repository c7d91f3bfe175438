//! Located addresses as IEC 61131-3 writes them (directly represented variables, 6.5.5; Annex A
//! `direct_variable`): `%`, a location prefix — `I` input, `Q` output, `M` memory — a size prefix — `X`
//! (or none) a bit, `B` a byte, `W` a word, `D` a double word, `L` a long word — and a position of
//! unsigned integers separated by dots.
//!
//! Every variable a manifest locates is a `BOOL`, so its address is a bit. The standard leaves the
//! meaning of a multi-level position to the implementation; the PLCs this tool writes for (matiec,
//! OpenPLC, CODESYS) and the manifest's examples write a bit as `BYTE.BIT` with the bit 0 to 7, so that
//! is what [`Address::bit`] accepts: `%IX0.2`, `%QX1.7`, `%MX10.0` (and `%I0.2`, the size left out).

use std::fmt;

/// Where a located variable is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Area {
    /// `%I`: a physical input, which the program reads.
    Input,
    /// `%Q`: a physical output, which the program writes.
    Output,
    /// `%M`: a memory location (another program, an HMI).
    Memory,
}

/// A `BOOL`'s located address: a bit of a byte of an area.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Address {
    /// The area.
    pub area: Area,
    /// The byte.
    pub byte: u32,
    /// The bit in the byte, 0 to 7.
    pub bit: u8,
}

impl Address {
    /// `text` as a `BOOL`'s address, or why it is not one (the message quotes it and says what was
    /// expected).
    pub fn bit(text: &str) -> Result<Address, String> {
        const EXPECTED: &str = "a BOOL's address is %IX (input), %QX (output) or %MX (memory) and BYTE.BIT, \
                                the bit 0 to 7, as %IX0.2";
        let Some(rest) = text.strip_prefix('%') else {
            let hint = match Address::bit(&format!("%{text}")) {
                Ok(a) => format!(": did you mean '{a}'?"),
                Err(_) => format!(" ({EXPECTED})"),
            };
            return Err(format!("'{text}' is no located address: it does not start with '%'{hint}"));
        };
        let mut chars = rest.chars();
        let area = match chars.next() {
            Some('I') => Area::Input,
            Some('Q') => Area::Output,
            Some('M') => Area::Memory,
            Some(c @ ('i' | 'q' | 'm')) => {
                let upper = format!("%{}", rest.to_ascii_uppercase());
                let hint = Address::bit(&upper).map(|a| format!(": did you mean '{a}'?")).unwrap_or_default();
                return Err(format!(
                    "'{text}': the location prefix is written in capitals ('{}'){hint}",
                    c.to_ascii_uppercase()
                ));
            }
            _ => return Err(format!("'{text}': after '%' comes I, Q or M ({EXPECTED})")),
        };
        let mut position = chars.as_str();
        if let Some(size) = position.chars().next().filter(char::is_ascii_alphabetic) {
            let what = match size {
                'X' => None,
                'B' => Some("a byte (8 bits)"),
                'W' => Some("a word (16 bits)"),
                'D' => Some("a double word (32 bits)"),
                'L' => Some("a long word (64 bits)"),
                _ => {
                    return Err(format!("'{text}': '{size}' is no size prefix (X, B, W, D or L; {EXPECTED})"))
                }
            };
            if let Some(what) = what {
                return Err(format!(
                    "'{text}' is {what}: a BOOL variable sits at a bit, %{}X<byte>.<bit>",
                    &rest[..1]
                ));
            }
            position = &position[1..];
        }
        if position == "*" {
            return Err(format!(
                "'{text}' is partly specified ('*'): a program's variable needs its full address ({EXPECTED})"
            ));
        }
        let fields: Vec<&str> = position.split('.').collect();
        if fields.iter().any(|f| f.is_empty() || !f.bytes().all(|b| b.is_ascii_digit())) {
            return Err(format!(
                "'{text}': the position is unsigned integers separated by dots ({EXPECTED})"
            ));
        }
        let [byte, bit] = fields.as_slice() else {
            return Err(format!("'{text}': a bit's position is BYTE.BIT, two numbers ({EXPECTED})"));
        };
        let byte: u32 = byte.parse().map_err(|_| format!("'{text}': byte {byte} is too large"))?;
        let bit = bit.parse::<u8>().ok().filter(|b| *b <= 7).ok_or_else(|| {
            format!(
                "'{text}': bit {bit} of a byte; a byte has bits 0 to 7 (the next byte's bit 0 is %{}X{}.0)",
                &rest[..1],
                byte.saturating_add(1)
            )
        })?;
        Ok(Address { area, byte, bit })
    }
}

impl fmt::Display for Address {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let area = match self.area {
            Area::Input => 'I',
            Area::Output => 'Q',
            Area::Memory => 'M',
        };
        write!(f, "%{area}X{}.{}", self.byte, self.bit)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bits_are_read_with_or_without_their_size() {
        assert_eq!(Address::bit("%IX0.2"), Ok(Address { area: Area::Input, byte: 0, bit: 2 }));
        assert_eq!(Address::bit("%Q1.7"), Ok(Address { area: Area::Output, byte: 1, bit: 7 }));
        assert_eq!(Address::bit("%MX10.0").unwrap().to_string(), "%MX10.0");
        assert_eq!(Address::bit("%I0.2"), Address::bit("%IX0.2"));
    }

    /// The addresses of issue 35's trial, each refused with its cause.
    #[test]
    fn what_is_no_bool_address_is_refused_naming_why() {
        let cases = [
            ("garbage", "does not start with '%'"),
            ("QX0.0", "did you mean '%QX0.0'?"),
            ("%QW0", "is a word (16 bits): a BOOL variable sits at a bit, %QX<byte>.<bit>"),
            ("%QB3", "is a byte"),
            ("%IX0.9", "bit 9 of a byte; a byte has bits 0 to 7 (the next byte's bit 0 is %IX1.0)"),
            ("%IX5", "BYTE.BIT, two numbers"),
            ("%IX1.2.3", "BYTE.BIT, two numbers"),
            ("%I*", "partly specified"),
            ("%ix0.0", "did you mean '%IX0.0'?"),
            ("%A0.0", "after '%' comes I, Q or M"),
            ("%IY0.0", "'Y' is no size prefix"),
            ("%IX0.", "unsigned integers separated by dots"),
            ("%IX-1.0", "unsigned integers"),
            ("%IX99999999999.0", "too large"),
            ("", "does not start with '%'"),
        ];
        for (text, why) in cases {
            let err = Address::bit(text).unwrap_err();
            assert!(err.contains(why), "{text}: {err}");
        }
    }
}

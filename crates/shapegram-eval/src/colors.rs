//! CGA's colour functions: hexadecimal colour strings (`"#rrggbb"`, `"#rrggbboo"` with
//! opacity) to and from RGB and HSV components, each in [0, 1] (hue in degrees).

/// A colour function.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum ColorFn {
    HexToR,
    HexToG,
    HexToB,
    HexToO,
    HexToH,
    HexToS,
    HexToV,
    RgbToHex,
    RgbOToHex,
    HsvToHex,
    HsvOToHex,
}

impl ColorFn {
    const ALL: [(&'static str, ColorFn, &'static str); 11] = [
        ("colorHexToR", Self::HexToR, "colorHexToR(hex)"),
        ("colorHexToG", Self::HexToG, "colorHexToG(hex)"),
        ("colorHexToB", Self::HexToB, "colorHexToB(hex)"),
        ("colorHexToO", Self::HexToO, "colorHexToO(hex)"),
        ("colorHexToH", Self::HexToH, "colorHexToH(hex)"),
        ("colorHexToS", Self::HexToS, "colorHexToS(hex)"),
        ("colorHexToV", Self::HexToV, "colorHexToV(hex)"),
        (
            "colorRGBToHex",
            Self::RgbToHex,
            "colorRGBToHex(red, green, blue)",
        ),
        (
            "colorRGBOToHex",
            Self::RgbOToHex,
            "colorRGBOToHex(red, green, blue, opacity)",
        ),
        (
            "colorHSVToHex",
            Self::HsvToHex,
            "colorHSVToHex(hue, saturation, value)",
        ),
        (
            "colorHSVOToHex",
            Self::HsvOToHex,
            "colorHSVOToHex(hue, saturation, value, opacity)",
        ),
    ];

    /// Every colour function's name.
    pub fn names() -> impl Iterator<Item = &'static str> {
        Self::ALL.iter().map(|(name, _, _)| *name)
    }

    /// The function of this name.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.iter().find(|(n, _, _)| *n == name).map(|e| e.1)
    }

    /// How many arguments it takes.
    pub fn arity(self) -> usize {
        match self {
            Self::RgbToHex | Self::HsvToHex => 3,
            Self::RgbOToHex | Self::HsvOToHex => 4,
            _ => 1,
        }
    }

    /// The signature shown in hints.
    pub fn signature(self) -> &'static str {
        Self::ALL.iter().find(|e| e.1 == self).map_or("", |e| e.2)
    }

    /// Whether the function reads a hexadecimal string (else it takes numbers).
    pub fn reads_hex(self) -> bool {
        self.arity() == 1
    }

    /// A component of the colour `hex`; 0 for a string that is not a colour (and for the
    /// opacity of a colour written without it).
    pub fn component(self, hex: &str) -> f64 {
        let Some((r, g, b, o)) = parse_hex(hex) else {
            return 0.0;
        };
        let (h, s, v) = rgb_to_hsv(r, g, b);
        match self {
            Self::HexToR => r,
            Self::HexToG => g,
            Self::HexToB => b,
            Self::HexToO => o.unwrap_or(0.0),
            Self::HexToH => h,
            Self::HexToS => s,
            _ => v,
        }
    }

    /// The hexadecimal string of the colour given by numbers (components clamped to [0, 1],
    /// hue taken modulo 360).
    pub fn hex(self, numbers: &[f64]) -> String {
        let (r, g, b) = match self {
            Self::HsvToHex | Self::HsvOToHex => hsv_to_rgb(numbers[0], numbers[1], numbers[2]),
            _ => (numbers[0], numbers[1], numbers[2]),
        };
        let byte = |c: f64| (c.clamp(0.0, 1.0) * 255.0).round() as u8;
        let mut out = format!("#{:02x}{:02x}{:02x}", byte(r), byte(g), byte(b));
        if let Some(&o) = numbers.get(3) {
            out += &format!("{:02x}", byte(o));
        }
        out
    }
}

/// Red, green, blue and (when written) opacity of `#rrggbb[oo]`, each in [0, 1].
fn parse_hex(hex: &str) -> Option<(f64, f64, f64, Option<f64>)> {
    let digits = hex.strip_prefix('#')?;
    if !(digits.len() == 6 || digits.len() == 8) || !digits.is_ascii() {
        return None;
    }
    let channel = |i: usize| {
        u8::from_str_radix(&digits[i..i + 2], 16)
            .ok()
            .map(|b| f64::from(b) / 255.0)
    };
    let opacity = match digits.len() {
        8 => Some(channel(6)?),
        _ => None,
    };
    Some((channel(0)?, channel(2)?, channel(4)?, opacity))
}

fn rgb_to_hsv(r: f64, g: f64, b: f64) -> (f64, f64, f64) {
    let max = r.max(g).max(b);
    let min = r.min(g).min(b);
    let delta = max - min;
    let hue = if delta == 0.0 {
        0.0
    } else if max == r {
        60.0 * ((g - b) / delta).rem_euclid(6.0)
    } else if max == g {
        60.0 * ((b - r) / delta + 2.0)
    } else {
        60.0 * ((r - g) / delta + 4.0)
    };
    let saturation = if max == 0.0 { 0.0 } else { delta / max };
    (hue, saturation, max)
}

fn hsv_to_rgb(h: f64, s: f64, v: f64) -> (f64, f64, f64) {
    let (h, s, v) = (h.rem_euclid(360.0), s.clamp(0.0, 1.0), v.clamp(0.0, 1.0));
    let c = v * s;
    let x = c * (1.0 - ((h / 60.0).rem_euclid(2.0) - 1.0).abs());
    let m = v - c;
    let (r, g, b) = match (h / 60.0) as u32 {
        0 => (c, x, 0.0),
        1 => (x, c, 0.0),
        2 => (0.0, c, x),
        3 => (0.0, x, c),
        4 => (x, 0.0, c),
        _ => (c, 0.0, x),
    };
    (r + m, g + m, b + m)
}

#[cfg(test)]
mod tests {
    use super::ColorFn::*;

    #[test]
    fn hex_strings_to_components_and_back() {
        assert_eq!(HexToR.component("#ff8000"), 1.0);
        assert_eq!(HexToG.component("#ff8000"), 128.0 / 255.0);
        assert_eq!(HexToH.component("#00ff00"), 120.0);
        assert_eq!(HexToS.component("#808080"), 0.0);
        assert_eq!(HexToV.component("#0000ff"), 1.0);
        assert_eq!(HexToO.component("#00000080"), 128.0 / 255.0);
        assert_eq!(HexToO.component("#000000"), 0.0);
        assert_eq!(HexToR.component("red"), 0.0);
        assert_eq!(RgbToHex.hex(&[1.0, 0.5, 2.0]), "#ff80ff");
        assert_eq!(RgbOToHex.hex(&[0.0, 0.0, 0.0, 1.0]), "#000000ff");
        assert_eq!(HsvToHex.hex(&[240.0, 1.0, 1.0]), "#0000ff");
        // Hue wraps: -185 is 175.
        assert_eq!(
            HsvToHex.hex(&[-185.0, 1.0, 1.0]),
            HsvToHex.hex(&[175.0, 1.0, 1.0])
        );
        assert_eq!(HsvOToHex.hex(&[0.0, 0.0, 1.0, 0.0]), "#ffffff00");
    }
}

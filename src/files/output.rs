//! Writing images: PNG and binary PPM (8-bit, gamma 2), and PFM and OpenEXR (linear f32),
//! atomically.
//!
//! The output file is first created as a temporary file in the destination's directory and
//! renamed over the destination only once complete, so a failed or interrupted run never
//! leaves a half-written image. The temporary file is created *before* rendering, so an
//! unwritable path fails in milliseconds instead of after a long render.

use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use image::ImageEncoder;
use image::codecs::png::PngEncoder;
use image::codecs::pnm::{PnmEncoder, PnmSubtype, SampleEncoding};
use tempfile::NamedTempFile;

use crate::error::{Error, io_reason};
use crate::files::image::Image;
use crate::tracer::math::real::to_f32;

/// An output format, chosen by the file extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// `.png`: 8-bit RGB, gamma 2.
    Png,
    /// `.ppm`: binary P6, 8-bit, gamma 2.
    Ppm,
    /// `.pfm`: linear 32-bit float RGB, no gamma (for measuring error).
    Pfm,
    /// `.exr`: OpenEXR, linear 32-bit float RGB, no gamma (what HDR tools read).
    Exr,
    /// `.rpart`: one shard of an image, to be merged (see [`crate::files::part`]).
    Part,
}

impl Format {
    /// The format named by `path`'s extension.
    pub fn from_path(path: &Path) -> Result<Format, Error> {
        let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("png") => Ok(Format::Png),
            Some("ppm") => Ok(Format::Ppm),
            Some("pfm") => Ok(Format::Pfm),
            Some("exr") => Ok(Format::Exr),
            Some("rpart") => Ok(Format::Part),
            _ => Err(Error::new(format!(
                "cannot tell the image format of '{}': use a .png, .ppm, .pfm, .exr or .rpart file name",
                path.display()
            ))),
        }
    }
}

/// An output file being prepared: created now, complete only after [`PendingOutput::write`].
pub struct PendingOutput {
    path: PathBuf,
    format: Format,
    temp: NamedTempFile,
}

impl PendingOutput {
    /// The format, from the destination's extension.
    pub fn format(&self) -> Format {
        self.format
    }

    /// Where the file is being prepared (removed when `self` is dropped unwritten).
    pub fn temp_path(&self) -> &Path {
        self.temp.path()
    }

    /// Checks the format and that the destination's directory is writable.
    pub fn create(path: &Path) -> Result<PendingOutput, Error> {
        let format = Format::from_path(path)?;
        Ok(PendingOutput { path: path.to_owned(), format, temp: temp_beside(path)? })
    }

    /// Encodes `image`, then renames the finished file onto the destination.
    pub fn write(self, image: &Image) -> Result<(), Error> {
        let format = self.format;
        self.write_with(|out| encode(image, format, out))
    }

    /// Writes 8-bit RGB bytes (e.g. a plot) as a PNG, then renames it into place.
    pub fn write_rgb8(self, width: u32, height: u32, rgb: &[u8]) -> Result<(), Error> {
        self.write_with(|out| {
            PngEncoder::new(out)
                .write_image(rgb, width, height, image::ExtendedColorType::Rgb8)
                .map_err(|e| e.to_string())
        })
    }

    /// Writes the file with `encode`, then renames it into place; on an error, nothing is
    /// left behind.
    pub fn write_with(
        self,
        encode: impl FnOnce(&mut BufWriter<&std::fs::File>) -> Result<(), String>,
    ) -> Result<(), Error> {
        persist(self.temp, &self.path, encode)
    }
}

/// Writes `text` (a report, a table) to `path` atomically.
pub fn write_text(path: &Path, text: &str) -> Result<(), Error> {
    persist(temp_beside(path)?, path, |out| out.write_all(text.as_bytes()).map_err(|e| io_reason(&e)))
}

/// A temporary file in `path`'s directory, to be renamed onto `path` once complete.
fn temp_beside(path: &Path) -> Result<NamedTempFile, Error> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let mut builder = tempfile::Builder::new();
    // A temporary file is private (0600); the finished file is an ordinary one, readable
    // as the umask allows, like any file the user's tools create.
    #[cfg(unix)]
    builder.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o666));
    builder
        .prefix(".raypool-")
        .suffix(".tmp")
        .tempfile_in(dir)
        .map_err(|e| Error::new(format!("cannot write '{}': {}", path.display(), io_reason(&e))))
}

/// Fills `temp` with `encode`, then renames it onto `path`.
fn persist(
    temp: NamedTempFile,
    path: &Path,
    encode: impl FnOnce(&mut BufWriter<&std::fs::File>) -> Result<(), String>,
) -> Result<(), Error> {
    let fail = |e: String| Error::new(format!("cannot write '{}': {e}", path.display()));
    let mut out = BufWriter::new(temp.as_file());
    encode(&mut out).map_err(&fail)?;
    out.flush().map_err(|e| fail(io_reason(&e)))?;
    drop(out);
    temp.persist(path).map_err(|e| fail(io_reason(&e.error)))?;
    Ok(())
}

/// Encodes `image` in `format` to `out`.
pub fn encode(image: &Image, format: Format, out: &mut impl Write) -> Result<(), String> {
    let (w, h) = (image.width, image.height);
    match format {
        Format::Png => PngEncoder::new(out)
            .write_image(&image.to_rgb8(), w, h, image::ExtendedColorType::Rgb8)
            .map_err(|e| e.to_string()),
        Format::Ppm => PnmEncoder::new(out)
            .with_subtype(PnmSubtype::Pixmap(SampleEncoding::Binary))
            .write_image(&image.to_rgb8(), w, h, image::ExtendedColorType::Rgb8)
            .map_err(|e| e.to_string()),
        Format::Pfm => write_pfm(image, out).map_err(|e| io_reason(&e)),
        Format::Exr => write_exr(image, out),
        Format::Part => Err("a .rpart file holds one shard of a render, not an image".to_string()),
    }
}

/// PFM: header `PF\n<w> <h>\n-1.0\n` (negative scale = little-endian), then f32 RGB rows
/// from the bottom row up, as the format specifies.
fn write_pfm(image: &Image, out: &mut impl Write) -> std::io::Result<()> {
    write!(out, "PF\n{} {}\n-1.0\n", image.width, image.height)?;
    for row in image.pixels.chunks_exact(image.width as usize).rev() {
        for p in row {
            for c in p.to_array() {
                out.write_all(&to_f32(c).to_le_bytes())?;
            }
        }
    }
    Ok(())
}

/// OpenEXR through the `image` crate's encoder, which needs to seek: encoded in memory, then
/// written out.
fn write_exr(image: &Image, out: &mut impl Write) -> Result<(), String> {
    let floats: Vec<u8> =
        image.pixels.iter().flat_map(|p| p.to_array()).flat_map(|c| to_f32(c).to_ne_bytes()).collect();
    let mut encoded = std::io::Cursor::new(Vec::new());
    image::codecs::openexr::OpenExrEncoder::new(&mut encoded)
        .write_image(&floats, image.width, image.height, image::ExtendedColorType::Rgb32F)
        .map_err(|e| e.to_string())?;
    out.write_all(encoded.get_ref()).map_err(|e| io_reason(&e))
}

/// Reads a PFM file written by any tool (either byte order) into linear RGB rows, top row
/// first: `(width, height, pixels)`.
pub fn read_pfm(bytes: &[u8]) -> Result<(u32, u32, Vec<[f32; 3]>), String> {
    let mut fields = Vec::new();
    let mut at = 0;
    while fields.len() < 4 {
        while at < bytes.len() && bytes[at].is_ascii_whitespace() {
            at += 1;
        }
        let start = at;
        while at < bytes.len() && !bytes[at].is_ascii_whitespace() {
            at += 1;
        }
        if start == at {
            return Err("truncated PFM header".into());
        }
        fields.push(std::str::from_utf8(&bytes[start..at]).map_err(|_| "PFM header is not text")?);
    }
    at += 1; // the single whitespace byte after the scale
    if fields[0] != "PF" {
        return Err(format!("not a colour PFM file (magic '{}')", fields[0]));
    }
    let number = |s: &str| s.parse::<u32>().map_err(|_| format!("bad PFM size '{s}'"));
    let (w, h) = (number(fields[1])?, number(fields[2])?);
    let scale: f32 = fields[3].parse().map_err(|_| format!("bad PFM scale '{}'", fields[3]))?;
    let data = bytes.get(at..).unwrap_or_default();
    if data.len() != w as usize * h as usize * 12 {
        return Err(format!("PFM data is {} bytes, expected {}", data.len(), w as usize * h as usize * 12));
    }
    let value = |b: &[u8]| {
        let b = [b[0], b[1], b[2], b[3]];
        if scale < 0.0 { f32::from_le_bytes(b) } else { f32::from_be_bytes(b) }
    };
    let mut rows: Vec<Vec<[f32; 3]>> = data
        .chunks_exact(w as usize * 12)
        .map(|row| {
            row.chunks_exact(12).map(|p| [value(&p[0..4]), value(&p[4..8]), value(&p[8..12])]).collect()
        })
        .collect();
    rows.reverse(); // stored bottom-to-top
    Ok((w, h, rows.concat()))
}

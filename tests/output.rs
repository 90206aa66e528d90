//! Image files read back: PFM (linear, bottom-to-top rows), PPM (P6) and PNG.

use raypool::files::image::Image;
use raypool::files::output::{Format, encode, read_pfm};
use raypool::tracer::math::real::{Real, Vec3, to_f32};

fn gradient(width: u32, height: u32) -> Image {
    let pixels = (0..width * height)
        .map(|k| {
            let (i, j) = ((k % width) as Real, (k / width) as Real);
            Vec3::new(i / width as Real, j / height as Real, 0.25 + i * j * 1e-3)
        })
        .collect();
    Image { width, height, pixels }
}

#[test]
fn pfm_reads_back_exactly_with_rows_bottom_to_top() {
    let image = gradient(7, 5);
    let mut bytes = Vec::new();
    encode(&image, Format::Pfm, &mut bytes).unwrap();
    assert!(bytes.starts_with(b"PF\n7 5\n-1.0\n"), "standard little-endian header");
    // The first stored row is the image's bottom row.
    let first = f32::from_le_bytes(bytes[12..16].try_into().unwrap());
    assert_eq!(first, to_f32(image.pixels[4 * 7].x));
    let (w, h, pixels) = read_pfm(&bytes).unwrap();
    assert_eq!((w, h), (7, 5));
    for (p, q) in image.pixels.iter().zip(&pixels) {
        assert_eq!(p.to_array().map(to_f32), *q);
    }
}

#[test]
fn ppm_is_binary_p6_with_gamma_2_bytes() {
    let image = gradient(6, 4);
    let mut bytes = Vec::new();
    encode(&image, Format::Ppm, &mut bytes).unwrap();
    // Header: magic, width, height, maxval, separated by whitespace, then one whitespace byte.
    let text = String::from_utf8_lossy(&bytes[..16]).into_owned();
    let fields: Vec<&str> = text.split_ascii_whitespace().take(4).collect();
    assert_eq!(fields, ["P6", "6", "4", "255"]);
    let header_len = bytes.len() - 6 * 4 * 3;
    assert!(bytes[header_len - 1].is_ascii_whitespace());
    assert_eq!(&bytes[header_len..], image.to_rgb8().as_slice());
    // Gamma 2: linear 0.25 → sqrt = 0.5 → 128.
    let mid = Image { width: 1, height: 1, pixels: vec![Vec3::splat(0.25)] };
    assert_eq!(mid.to_rgb8(), vec![128, 128, 128]);
}

#[test]
fn png_decodes_to_the_same_bytes() {
    let image = gradient(9, 3);
    let mut bytes = Vec::new();
    encode(&image, Format::Png, &mut bytes).unwrap();
    let decoded = image::load_from_memory(&bytes).unwrap().to_rgb8();
    assert_eq!(decoded.dimensions(), (9, 3));
    assert_eq!(decoded.into_raw(), image.to_rgb8());
}

#[test]
fn out_of_range_values_clamp_instead_of_wrapping() {
    let image = Image {
        width: 3,
        height: 1,
        pixels: vec![Vec3::splat(-1.0), Vec3::splat(4.0), Vec3::splat(Real::NAN)],
    };
    assert_eq!(image.to_rgb8(), vec![0, 0, 0, 255, 255, 255, 0, 0, 0]);
}

#[test]
fn exr_decodes_to_the_same_floats_as_the_pfm() {
    let image = gradient(9, 4);
    let (mut exr, mut pfm) = (Vec::new(), Vec::new());
    encode(&image, Format::Exr, &mut exr).unwrap();
    encode(&image, Format::Pfm, &mut pfm).unwrap();
    assert!(exr.starts_with(&[0x76, 0x2f, 0x31, 0x01]), "OpenEXR's magic number");
    let decoded = image::load_from_memory_with_format(&exr, image::ImageFormat::OpenExr).unwrap().to_rgb32f();
    assert_eq!(decoded.dimensions(), (9, 4));
    let (_, _, floats) = read_pfm(&pfm).unwrap();
    assert_eq!(decoded.pixels().map(|p| p.0).collect::<Vec<_>>(), floats, "linear floats, top row first");
}

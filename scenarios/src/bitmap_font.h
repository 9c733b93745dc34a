// A small bitmap font of the project's own for the pictures a run leaves (topdown.png): printable
// ASCII, the degree sign and the multiplication sign, 5 pixels wide and 9 high (7 above the
// baseline, 2 for descenders), no font file needed.
#pragma once

#include <cstdint>
#include <string>

namespace ovpc::scenarios::internal {

constexpr int kGlyphWidth = 5;
constexpr int kGlyphHeight = 9;   ///< rows; the baseline is below row 6
constexpr int kGlyphAdvance = 6;  ///< pixels from one character to the next, at scale 1
constexpr int kLineHeight = 11;   ///< pixels from one line to the next, at scale 1

/// The glyph's kGlyphHeight rows, top first, bit 4 the leftmost column; nullptr when the font has
/// no glyph for `code_point`.
const std::uint8_t* FindGlyph(char32_t code_point);

/// UTF-8 text as code points; a byte that does not start a well-formed sequence is U+FFFD (the font
/// has no glyph for it, so it shows as a box).
std::u32string DecodeUtf8(const std::string& text);

/// The text's width in pixels at `scale` (one advance per code point, the last without its gap).
int TextWidth(const std::string& text, int scale = 1);

}  // namespace ovpc::scenarios::internal

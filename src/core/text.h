#pragma once
// Text that comes from files users hand us: names and comments in whatever encoding their tool wrote,
// and bytes that must never reach a terminal unescaped.
#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>

namespace mocap {

/// True when `bytes` is well-formed UTF-8 (no overlong forms, surrogates or code points past U+10FFFF).
bool IsValidUtf8(std::string_view bytes);

/// `bytes` as UTF-8: kept as it is when it already is valid UTF-8, else every byte is read as
/// Windows-1252 (the code page of the Windows tools that write most such files; the five bytes it leaves
/// undefined map to the Latin-1 control characters of the same value). Names stay readable and stored
/// sessions stay valid JSON, whatever the source's encoding.
std::string TextToUtf8(std::string_view bytes);

/// TextToUtf8 applied to each '\n'-separated line on its own, so one line in another encoding does not
/// change how the valid UTF-8 lines around it are read.
std::string LinesToUtf8(std::string_view text);

/// `text` fit to be shown inside an error message: in single quotes, with control bytes, the quote, the
/// backslash and bytes that are not valid UTF-8 written as \xNN (a crafted file cannot drive the user's
/// terminal), and cut after `max_bytes` input bytes with "..." appended.
std::string QuoteForMessage(std::string_view text, size_t max_bytes = 80);

/// A file's extension in lower case (".PNG" -> ".png"), ".jpeg" spelt ".jpg": file names users give may
/// use any case, and the tool writes one spelling of each.
std::string LowerExtension(const std::filesystem::path& file);

}  // namespace mocap

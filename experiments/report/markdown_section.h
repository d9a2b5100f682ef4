#pragma once
// Replacing one generated section of a Markdown file, so several benchmarks can share docs/benchmarks.md.

#include <QString>

namespace sc::report {

/// Replaces the text between "<!-- NAME:start -->" and "<!-- NAME:end -->" in `file` with `body` (markers kept),
/// or appends a new marked section when there is none. Creates the file if needed. Returns false on I/O error.
bool writeMarkdownSection(const QString& file, const QString& name, const QString& body);

}  // namespace sc::report

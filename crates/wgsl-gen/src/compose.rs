//! Composition of WGSL parts into one module, and naga validation with readable errors.

use std::fmt;

use gpu_layout::WgslModule;

/// A WGSL module assembled from named parts (generated declarations, hand-written
/// library code, kernels), concatenated in order.
#[derive(Clone, Debug, Default)]
pub struct ComposedShader {
    name: String,
    source: String,
    /// `(label, first line)` of each part, 1-based lines of `source`.
    parts: Vec<(String, usize)>,
}

/// A module that naga parsed and validated.
#[derive(Debug)]
pub struct ValidatedModule {
    /// The parsed module.
    pub module: naga::Module,
    /// naga's validation results.
    pub info: naga::valid::ModuleInfo,
}

/// A shader that failed to parse or validate, with naga's rendered message.
#[derive(Clone, Debug)]
pub struct ShaderError {
    /// The composed module's name.
    pub module: String,
    /// naga's diagnostic, rendered against the composed source, with a map of which part
    /// (file) each line range comes from.
    pub rendered: String,
    /// The label (file) of the part that the first reported line falls in, if known.
    pub file: Option<String>,
}

impl fmt::Display for ShaderError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.file {
            Some(file) => writeln!(f, "WGSL module `{}` is invalid (error in {file}):", self.module)?,
            None => writeln!(f, "WGSL module `{}` is invalid:", self.module)?,
        }
        write!(f, "{}", self.rendered)
    }
}

impl std::error::Error for ShaderError {}

impl ComposedShader {
    /// An empty module called `name`.
    pub fn new(name: impl Into<String>) -> Self {
        Self { name: name.into(), ..Self::default() }
    }

    /// Appends a part, labelled by `label` (normally its path in the repository).
    pub fn with_part(mut self, label: impl Into<String>, source: &str) -> Self {
        let label = label.into();
        if !self.source.is_empty() && !self.source.ends_with('\n') {
            self.source.push('\n');
        }
        let first_line = self.source.lines().count() + 1;
        self.source.push_str(&format!("// ---- {label} ----\n"));
        self.source.push_str(source);
        self.parts.push((label, first_line));
        self
    }

    /// Appends every part of `module` ([`WgslModule::parts`]: its dependencies' then its own
    /// declarations and library), each labelled `<module>: declarations` or
    /// `<module>: library`.
    pub fn with_module(mut self, module: &WgslModule) -> Self {
        for (name, declarations, library) in module.parts() {
            self = self
                .with_part(format!("{name}: declarations"), declarations)
                .with_part(format!("{name}: library"), library);
        }
        self
    }

    /// A module called `<module name>.composed` holding [`with_module`](Self::with_module)'s parts.
    pub fn of_module(module: &WgslModule) -> Self {
        Self::new(format!("{}.composed", module.name)).with_module(module)
    }

    /// The module's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The composed WGSL source.
    pub fn source(&self) -> &str {
        &self.source
    }

    /// The label of the part containing 1-based `line`, and the line number inside it.
    pub fn locate(&self, line: usize) -> Option<(&str, usize)> {
        self.parts.iter().rev().find(|(_, first)| *first <= line).map(|(label, first)| (label.as_str(), line - first))
    }

    fn part_map(&self) -> String {
        let mut map = String::from("composed from:\n");
        for (i, (label, first)) in self.parts.iter().enumerate() {
            let last = self.parts.get(i + 1).map_or(self.source.lines().count(), |(_, next)| next - 1);
            map.push_str(&format!("  lines {first}-{last}: {label} (its line k is composed line {first} + k)\n"));
        }
        map
    }

    fn error(&self, rendered: String, line: Option<usize>) -> ShaderError {
        let file = line.and_then(|l| self.locate(l)).map(|(label, local)| format!("{label}:{local}"));
        ShaderError { module: self.name.clone(), rendered: format!("{rendered}\n{}", self.part_map()), file }
    }

    /// Parses the module with naga's WGSL front end.
    pub fn parse(&self) -> Result<naga::Module, ShaderError> {
        naga::front::wgsl::parse_str(&self.source).map_err(|e| {
            let line = e.location(&self.source).map(|l| l.line_number as usize);
            self.error(e.emit_to_string_with_path(&self.source, &self.name), line)
        })
    }

    /// Parses and validates the module with every naga validation flag and the given
    /// capabilities.
    pub fn validate_with(&self, capabilities: naga::valid::Capabilities) -> Result<ValidatedModule, ShaderError> {
        let module = self.parse()?;
        let mut validator = naga::valid::Validator::new(naga::valid::ValidationFlags::all(), capabilities);
        match validator.validate(&module) {
            Ok(info) => Ok(ValidatedModule { module, info }),
            Err(e) => {
                let line = e.location(&self.source).map(|l| l.line_number as usize);
                Err(self.error(e.emit_to_string_with_path(&self.source, &self.name), line))
            }
        }
    }

    /// [`validate_with`](Self::validate_with) with naga's default capabilities.
    pub fn validate(&self) -> Result<ValidatedModule, ShaderError> {
        self.validate_with(naga::valid::Capabilities::default())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_broken_part_is_reported_with_its_file_and_naga_message() {
        let shader = ComposedShader::new("broken")
            .with_part("shaders/generated/a.wgsl", "const A: u32 = 1u;\n")
            .with_part("shaders/b.wgsl", "fn f() -> u32 {\n    return A + 1.5;\n}\n");
        let error = shader.validate().unwrap_err();
        let text = error.to_string();
        assert!(error.file.as_deref().is_some_and(|f| f.starts_with("shaders/b.wgsl:")), "{text}");
        assert!(text.contains("shaders/b.wgsl"), "{text}");
        assert!(text.contains("error"), "{text}");

        let syntax = ComposedShader::new("syntax").with_part("shaders/c.wgsl", "fn g( {}");
        let error = syntax.validate().unwrap_err();
        assert_eq!(error.file.as_deref(), Some("shaders/c.wgsl:1"), "{error}");
    }

    #[test]
    fn locate_maps_composed_lines_to_parts() {
        let shader = ComposedShader::new("m").with_part("a", "x\ny\n").with_part("b", "z\n");
        assert_eq!(shader.locate(1), Some(("a", 0)));
        assert_eq!(shader.locate(3), Some(("a", 2)));
        assert_eq!(shader.locate(5), Some(("b", 1)));
    }
}

"""One shader source, three languages: the project's GLSL subset printed as GLSL, HLSL and WGSL.

Public objects: ``LANGUAGES``, ``translate``, ``ShaderSourceError``.

Every function of the includes is written once, in GLSL (``handoff/shaders/source/*.glsl`` and the statements
:mod:`handoff.shaders.include` generates from the basis), as MaterialX keeps one GLSL body per node
(``libraries/pbrlib/genglsl``) that its other targets inherit through a spelling layer. HLSL here is such a
spelling of the same statements (types, intrinsics, texture reads, ``static const``). WGSL differs in its
declarations (``let``/``var`` with ``name: type``, ``fn name(param: type) -> type``), its conditional expression
(``select``) and its immutable parameters, so MaterialX reaches it by translating its GLSL with a compiler; here the
subset is small enough to translate line by line, and the WGSL stays readable.

The subset (what :func:`translate` accepts; anything else is a :class:`ShaderSourceError` naming the line):

* top level: ``//`` comments, ``const TYPE NAME = EXPR;``, ``const TYPE NAME[N] = TYPE[N](…);``, a ``struct`` of
  fields, and functions ``TYPE name(params)`` with ``{`` on the next line and ``}`` closing alone; a switch, the
  three lines ``#ifndef NAME`` / ``#define NAME true|false`` / ``#endif``, which HLSL keeps and WGSL (no
  preprocessor) declares ``override NAME: bool = …;``, a constant its pipeline may set;
* parameters ``TYPE name``, ``out TYPE name`` (GLSL and HLSL only: a function with one is left out of WGSL, which
  has no out parameters), ``TYPE name[N]``, and textures ``sampler2D name``: in HLSL and WGSL a function whose
  parameters hold textures takes one sampler, ``linearClamp``, after the last of them, and calls pass it there;
* one statement per line: ``TYPE name = EXPR;``, ``TYPE name;``, ``TYPE name[N];``, assignments (``=``, ``+=``,
  ``-=``, ``*=``), ``return``, ``if (…)``/``else`` and ``for (int i = A; i < B; ++i)`` with the brace on the next
  line; a parameter a body assigns is copied into a variable in WGSL (parameters are immutable there);
* expressions: GLSL's operators, swizzles and calls; a conditional ``(c ? a : b)`` becomes WGSL's
  ``select(b, a, c)`` (both evaluated: a body never relies on one side not running); ``textureLod(t, uv, 0.0)``
  the language's level-0 read; vector arguments of ``clamp``, ``min`` and ``max`` given as vectors (WGSL does not
  widen a scalar there).
"""

from __future__ import annotations

import re

from basis.validation import ParameterError

__all__ = ["LANGUAGES", "ShaderSourceError", "translate"]

LANGUAGES = ("glsl", "hlsl", "wgsl")


class ShaderSourceError(ParameterError):
    """A line of a shader source outside the subset :func:`translate` knows."""


#: GLSL type → (HLSL, WGSL).
_TYPES = {
    "float": ("float", "f32"),
    "int": ("int", "i32"),
    "uint": ("uint", "u32"),
    "bool": ("bool", "bool"),
    "vec2": ("float2", "vec2f"),
    "vec3": ("float3", "vec3f"),
    "vec4": ("float4", "vec4f"),
    "bvec2": ("bool2", "vec2<bool>"),
    "bvec3": ("bool3", "vec3<bool>"),
    "bvec4": ("bool4", "vec4<bool>"),
    "sampler2D": ("Texture2D<float4>", "texture_2d<f32>"),
}
#: GLSL function → (HLSL, WGSL), where the names differ.
_FUNCTIONS = {
    "mix": ("lerp", "mix"),
    "atan": ("atan2", "atan2"),
    "floatBitsToUint": ("asuint", "bitcast<u32>"),
    "floatBitsToInt": ("asint", "bitcast<i32>"),
    "intBitsToFloat": ("asfloat", "bitcast<f32>"),
    "fract": ("frac", "fract"),
    "inversesqrt": ("rsqrt", "inverseSqrt"),
}
#: The one sampler of the HLSL and WGSL functions that read textures.
SAMPLER = "linearClamp"

_IDENTIFIER = r"[A-Za-z_]\w*"
_FUNCTION = re.compile(rf"^(?P<type>{_IDENTIFIER})\s+(?P<name>{_IDENTIFIER})\s*\((?P<parameters>.*)\)\s*$")
_CONST = re.compile(
    rf"^const\s+(?P<type>{_IDENTIFIER})\s+(?P<name>{_IDENTIFIER})(?:\[(?P<size>\d+)\])?\s*=\s*(?P<value>.*);$", re.S
)
_DECLARATION = re.compile(
    rf"^(?P<type>{_IDENTIFIER})\s+(?P<name>{_IDENTIFIER})(?:\[(?P<size>\d+)\])?\s*(?:=\s*(?P<value>.*))?;(?P<comment>\s*//.*)?$"
)
_FOR = re.compile(
    rf"^for\s*\(\s*int\s+(?P<name>{_IDENTIFIER})\s*=\s*(?P<start>[^;]+);\s*(?P<condition>[^;]+);\s*\+\+(?P=name)\s*\)$"
)
_STRUCT_FIELD = re.compile(rf"^(?P<type>{_IDENTIFIER})\s+(?P<name>{_IDENTIFIER});(?P<comment>\s*//.*)?$")


def _split_comment(line: str) -> tuple[str, str]:
    """(code, the comment with the spaces before it) of one line; ``//`` inside no string (the subset has none)."""
    index = line.find("//")
    if index < 0:
        return line.rstrip(), ""
    code = line[:index].rstrip()
    return code, line[len(code) :].rstrip() if code else line[index:].rstrip()


def _top_level_split(text: str, separator: str) -> list[str]:
    """``text`` split at ``separator`` (one character) outside parentheses and brackets."""
    parts, depth, start = [], 0, 0
    for index, character in enumerate(text):
        if character in "([":
            depth += 1
        elif character in ")]":
            depth -= 1
        elif character == separator and depth == 0:
            parts.append(text[start:index])
            start = index + 1
    return parts + [text[start:]]


def _ternaries_to_select(expression: str) -> str:
    """WGSL's ``select(b, a, c)`` for every ``c ? a : b`` of ``expression`` (nested ones too, innermost first
    within each parenthesised group)."""
    result, index = [], 0
    while index < len(expression):  # translate the inside of every group first
        character = expression[index]
        if character == "(":
            depth, end = 1, index + 1
            while depth:
                depth += {"(": 1, ")": -1}.get(expression[end], 0)
                end += 1
            result.append("(" + _ternaries_to_select(expression[index + 1 : end - 1]) + ")")
            index = end
        else:
            result.append(character)
            index += 1
    text = "".join(result)
    arguments = _top_level_split(text, ",")
    if len(arguments) > 1:
        return ",".join(_ternary_at_top(argument) for argument in arguments)
    return _ternary_at_top(text)


def _ternary_at_top(text: str) -> str:
    """One comma-free expression whose groups are translated: its own top-level ``c ? a : b``, if any."""
    depth, question = 0, -1
    for index, character in enumerate(text):
        if character in "([":
            depth += 1
        elif character in ")]":
            depth -= 1
        elif character == "?" and depth == 0:
            question = index
            break
    if question < 0:
        return text
    depth, nested, colon = 0, 0, -1
    for index in range(question + 1, len(text)):
        character = text[index]
        if character in "([":
            depth += 1
        elif character in ")]":
            depth -= 1
        elif depth == 0 and character == "?":
            nested += 1
        elif depth == 0 and character == ":":
            if nested == 0:
                colon = index
                break
            nested -= 1
    if colon < 0:
        raise ShaderSourceError(f"a conditional without its ':' in {text.strip()!r}")
    condition, chosen, other = text[:question], text[question + 1 : colon], text[colon + 1 :]
    lead = condition[: len(condition) - len(condition.lstrip())]
    return f"{lead}select({_ternary_at_top(other).strip()}, {_ternary_at_top(chosen).strip()}, {condition.strip()})"


class _Language:
    """What differs between two targets, for the statements of one document."""

    def __init__(self, language: str, signatures: dict[str, list[tuple[str, str, str, str]]]):
        self.language = language
        self.signatures = signatures  # function → [(qualifier, GLSL type, name, array size)]

    @property
    def wgsl(self) -> bool:
        return self.language == "wgsl"

    def type(self, glsl_type: str) -> str:
        if self.language == "glsl" or glsl_type not in _TYPES:
            return glsl_type  # a struct keeps its name
        return _TYPES[glsl_type][0 if self.language == "hlsl" else 1]

    def expression(self, text: str) -> str:
        """An expression in this language: types, intrinsics, texture reads, samplers passed on, conditionals."""
        if self.language == "glsl":
            return text
        text = self._texture_reads(text)
        text = self._pass_sampler(text)
        index = 0 if self.language == "hlsl" else 1
        text = re.sub(
            r"\b(" + "|".join(map(re.escape, _FUNCTIONS)) + r")\s*\(",
            lambda match: _FUNCTIONS[match.group(1)][index] + "(",
            text,
        )
        text = re.sub(
            r"\b(" + "|".join(t for t in _TYPES if t != "sampler2D") + r")\s*\(",
            lambda match: self.type(match.group(1)) + "(",
            text,
        )
        return _ternaries_to_select(text) if self.wgsl else text

    def _texture_reads(self, text: str) -> str:
        def read(match: re.Match) -> str:
            texture, rest = match.group(1), match.group(2)
            arguments = _top_level_split(rest, ",")
            if len(arguments) != 2 or arguments[1].strip() not in ("0", "0.0"):
                raise ShaderSourceError(f"textureLod reads level 0 only, got textureLod({texture}, {rest})")
            uv = arguments[0].strip()
            if self.wgsl:
                return f"textureSampleLevel({texture}, {SAMPLER}, {uv}, 0.0)"
            return f"{texture}.SampleLevel({SAMPLER}, {uv}, 0)"

        return _replace_calls(
            text, "textureLod", lambda arguments: read(re.match(r"\s*(\w+)\s*,(.*)", arguments, re.S))
        )

    def _pass_sampler(self, text: str) -> str:
        """Calls of this document's functions that take textures get ``linearClamp`` after the last one."""
        for name, parameters in self.signatures.items():
            last = max((i for i, p in enumerate(parameters) if p[1] == "sampler2D"), default=-1)
            if last < 0:
                continue

            def passed(arguments: str, last=last, name=name) -> str:
                parts = _top_level_split(arguments, ",")
                parts.insert(last + 1, f" {SAMPLER}")
                return f"{name}(" + ",".join(parts) + ")"

            text = _replace_calls(text, name, passed, keep_name=False)
        return text


def _replace_calls(text: str, name: str, replacement, keep_name: bool = False) -> str:
    """``text`` with every call ``name(arguments)`` replaced by ``replacement(arguments)`` (arguments translated first,
    innermost calls first)."""
    pattern = re.compile(rf"\b{re.escape(name)}\s*\(")
    output, index = [], 0
    while True:
        match = pattern.search(text, index)
        if match is None:
            return "".join(output) + text[index:]
        depth, end = 1, match.end()
        while depth:
            if end >= len(text):
                raise ShaderSourceError(f"unbalanced parentheses after {name}( in {text.strip()!r}")
            depth += {"(": 1, ")": -1}.get(text[end], 0)
            end += 1
        inner = _replace_calls(text[match.end() : end - 1], name, replacement, keep_name)
        output.append(text[index : match.start()] + replacement(inner))
        index = end


def _parameters(text: str) -> list[tuple[str, str, str, str]]:
    """(qualifier, type, name, array size) of each parameter of a GLSL function header."""
    found = []
    for part in _top_level_split(text, ","):
        part = part.strip()
        if not part:
            continue
        match = re.fullmatch(rf"(?:(out|in)\s+)?({_IDENTIFIER})\s+({_IDENTIFIER})(?:\[(\d+)\])?", part)
        if match is None:
            raise ShaderSourceError(f"a parameter the subset does not know: {part!r}")
        found.append((match.group(1) or "", match.group(2), match.group(3), match.group(4) or ""))
    return found


def _signatures(lines: list[str]) -> dict[str, list[tuple[str, str, str, str]]]:
    signatures = {}
    for line in lines:
        code, _ = _split_comment(line)
        match = _FUNCTION.match(code)
        if match and not code.startswith(("return", "const", "struct")):
            signatures[match.group("name")] = _parameters(match.group("parameters"))
    return signatures


def _assigned(name: str, body: list[str]) -> bool:
    """Whether ``name`` is assigned (``=``, ``+=``, …, an element or a field of it too) by a line of ``body`` other
    than its declaration."""
    pattern = re.compile(rf"(?<![\w.])\b{re.escape(name)}\b(?:\[[^\]]*\])?(?:\.\w+)?\s*(?:[-+*/]?=)(?!=)")
    declared = re.compile(rf"^\s*{_IDENTIFIER}\s+{re.escape(name)}\b")
    return any(pattern.search(code) and not declared.match(code) for code in (_split_comment(line)[0] for line in body))


def translate(source: str, language: str) -> str:
    """``source`` (the subset of the module docstring) in ``language`` ("glsl", "hlsl" or "wgsl"); GLSL comes back as
    it is. Comments and blank lines are kept where they stand.

    >>> print(translate("float twice(float x)\\n{\\n    float y = x > 0.0 ? x : -x;\\n    return y * 2.0;\\n}", "wgsl"))
    fn twice(x: f32) -> f32
    {
        let y: f32 = select(-x, x, x > 0.0);
        return y * 2.0;
    }
    """
    if language not in LANGUAGES:
        raise ShaderSourceError(f"language must be one of {list(LANGUAGES)}, got {language!r}")
    if language == "glsl":
        return source
    lines = source.splitlines()
    target = _Language(language, _signatures(lines))
    output, index = [], 0
    while index < len(lines):
        line = lines[index]
        code, comment = _split_comment(line)
        stripped = code.strip()
        if not stripped:
            output.append(line.rstrip())
            index += 1
            continue
        if stripped.startswith("const "):
            end = index
            while not _split_comment(lines[end])[0].rstrip().endswith(";"):  # an array's items, one a line
                end += 1
                if end == len(lines):
                    raise ShaderSourceError(f"line {index + 1}: a constant without its ';'")
            if end > index:
                stripped, comment = "\n".join(lines[index : end + 1]).strip(), ""
            output.append(_constant(stripped, target) + comment)
            index = end + 1
            continue
        switch = re.fullmatch(rf"#ifndef ({_IDENTIFIER})", stripped)
        if switch:  # a switch: #ifndef NAME / #define NAME true|false / #endif
            name = switch.group(1)
            default = re.fullmatch(rf"#define {name} (true|false)", lines[index + 1].strip())
            if default is None or lines[index + 2].strip() != "#endif":
                raise ShaderSourceError(f"line {index + 1}: a switch is #ifndef NAME, #define NAME true|false, #endif")
            if target.wgsl:  # a pipeline-overridable constant, which the pipeline specialises as a define would
                output.append(f"override {name}: bool = {default.group(1)};")
            else:
                output += [line.rstrip() for line in lines[index : index + 3]]
            index += 3
            continue
        if stripped.startswith("struct "):
            end = lines.index("};", index)
            output += _struct(lines[index : end + 1], target)
            index = end + 1
            continue
        match = _FUNCTION.match(stripped)
        if match is None:
            raise ShaderSourceError(f"line {index + 1}: not a declaration the subset knows: {line.strip()!r}")
        end = index + 1
        if lines[end].strip() != "{":
            raise ShaderSourceError(f"line {end + 1}: a function's body opens with '{{' on its own line")
        depth, close = 0, end
        while True:
            depth += lines[close].count("{") - lines[close].count("}")
            if depth == 0:
                break
            close += 1
        body = lines[end + 1 : close]
        output += _function(match, body, comment, target)
        index = close + 1
    return "\n".join(output) + ("\n" if source.endswith("\n") else "")


def _constant(code: str, target: _Language) -> str:
    match = _CONST.match(code)
    if match is None:
        raise ShaderSourceError(f"a constant the subset does not know: {code!r}")
    kind, name, size, value = match.group("type", "name", "size", "value")
    if size:  # an array: TYPE[N](…)
        values = re.fullmatch(rf"{kind}\[{size}\]\((?P<items>.*)\)", value.strip(), re.S)
        if values is None:
            raise ShaderSourceError(f"an array constant is written {kind}[{size}](…): {code!r}")
        items = target.expression(values.group("items"))
        if target.wgsl:  # indexed per pixel: a private array (a const one may be indexed by constants only)
            element = target.type(kind)
            return f"var<private> {name}: array<{element}, {size}> = array<{element}, {size}>({items});"
        return f"static const {target.type(kind)} {name}[{size}] = {{{items}}};"
    if target.wgsl:
        return f"const {name}: {target.type(kind)} = {target.expression(value)};"
    return f"static const {target.type(kind)} {name} = {target.expression(value)};"


def _struct(lines: list[str], target: _Language) -> list[str]:
    name = re.fullmatch(rf"struct\s+({_IDENTIFIER})", lines[0].strip())
    if name is None or lines[1].strip() != "{":
        raise ShaderSourceError(f"a struct is 'struct Name', '{{' on the next line: {lines[0]!r}")
    output = [f"struct {name.group(1)}", "{"]
    for line in lines[2:-1]:
        code, comment = _split_comment(line)
        field = _STRUCT_FIELD.match(code.strip())
        if field is None:
            raise ShaderSourceError(f"a struct field is 'TYPE name;': {line!r}")
        kind, member = target.type(field.group("type")), field.group("name")
        output.append(f"    {member}: {kind},{comment}" if target.wgsl else f"    {kind} {member};{comment}")
    return output + ["}" if target.wgsl else "};"]


def _function(match: re.Match, body: list[str], comment: str, target: _Language) -> list[str]:
    kind, name = match.group("type"), match.group("name")
    parameters = _parameters(match.group("parameters"))
    if target.wgsl and any(qualifier == "out" for qualifier, *_ in parameters):
        return [f"// {name}: GLSL and HLSL only (WGSL has no out parameters)"]
    copies = []
    rendered = []
    last_texture = max((i for i, p in enumerate(parameters) if p[1] == "sampler2D"), default=-1)
    for position, (qualifier, ptype, pname, size) in enumerate(parameters):
        spelled = target.type(ptype)
        if target.wgsl:
            written = pname
            if _assigned(pname, body):
                written = pname + "In"
                copies.append(f"    var {pname} = {written};")
            rendered.append(f"{written}: array<{spelled}, {size}>" if size else f"{written}: {spelled}")
        else:
            rendered.append(f"{qualifier + ' ' if qualifier else ''}{spelled} {pname}{f'[{size}]' if size else ''}")
        if position == last_texture:
            rendered.append(f"{SAMPLER}: sampler" if target.wgsl else f"SamplerState {SAMPLER}")
    header = (
        f"fn {name}({', '.join(rendered)})" + ("" if kind == "void" else f" -> {target.type(kind)}")
        if target.wgsl
        else f"{target.type(kind)} {name}({', '.join(rendered)})"
    )
    output = [header + comment, "{", *copies]
    for line in body:
        output.append(_statement(line, body, target))
    return output + ["}"]


def _statement(line: str, body: list[str], target: _Language) -> str:
    code, comment = _split_comment(line)
    indent = code[: len(code) - len(code.lstrip())]
    text = code.strip()
    if not text or text in ("{", "}", "else"):
        return line.rstrip()
    loop = _FOR.match(text)
    if loop:
        name, start, condition = loop.group("name", "start", "condition")
        if target.wgsl:
            return f"{indent}for (var {name} = {start.strip()}; {condition.strip()}; {name}++){comment}"
        return f"{indent}for (int {name} = {start.strip()}; {condition.strip()}; ++{name}){comment}"
    condition = re.fullmatch(r"(else\s+)?if\s*\((.*)\)", text)
    if condition:
        return f"{indent}{condition.group(1) or ''}if ({target.expression(condition.group(2))}){comment}"
    returned = re.fullmatch(r"return(?:\s+(.*))?;", text)
    if returned:
        value = f" {target.expression(returned.group(1))}" if returned.group(1) else ""
        return f"{indent}return{value};{comment}"
    assignment = re.fullmatch(r"([\w.\[\]() +&-]+?)\s*([-+*/]?=)(?!=)\s*(.*);", text)
    if assignment and not _DECLARATION.match(text):
        left, operator, right = assignment.groups()
        return f"{indent}{target.expression(left)} {operator} {target.expression(right)};{comment}"
    declaration = _DECLARATION.match(text)
    if declaration and declaration.group("type") not in ("return", "else") and not re.match(r"^\w+\s*[-+*/]?=", text):
        kind, name, size, value = declaration.group("type", "name", "size", "value")
        own = declaration.group("comment") or ""
        if not target.wgsl:
            spelled = target.type(kind)
            array = f"[{size}]" if size else ""
            assigned = f" = {target.expression(value)}" if value is not None else ""
            return f"{indent}{spelled} {name}{array}{assigned};{own}{comment}"
        spelled = f"array<{target.type(kind)}, {size}>" if size else target.type(kind)
        if value is None:
            return f"{indent}var {name}: {spelled};{own}{comment}"
        keyword = "var" if _assigned(name, body) else "let"
        return f"{indent}{keyword} {name}: {spelled} = {target.expression(value)};{own}{comment}"
    if re.fullmatch(rf"{_IDENTIFIER}\s*\(.*\);", text):  # a call for its effect
        return f"{indent}{target.expression(text[:-1])};{comment}"
    raise ShaderSourceError(f"a statement the subset does not know: {text!r}")

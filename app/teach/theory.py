"""Natura's theory pages (one per thesis in ``docs/theory/``) read by the program: their anchored
sections, TeX turned into readable Unicode (a terminal, the window's panel) or MathML (the HTML
handouts), and the tags of the code that cite them.

Every tag in the code, ``spec/003 eq. 7.18`` or ``spec/003 §2.9 a``, has an anchor on its
thesis's page (``<a id="eq-7.18"></a>``, ``<a id="s-2.9-a"></a>``) right before a heading. A
section is that heading and what follows it up to the next anchor or heading of the same or a
higher level (:func:`section_body`); its *own* text stops at the next anchor of any level
(:attr:`Entry.body`). Bodies keep their math as ``$TeX$`` and ``$$TeX$$`` (one line each) and
drop the rest of the markdown (bold, code spans, links; bullets become "•", tables "a · b"):
:func:`math_to_unicode` and :func:`math_to_html` turn them into what is shown.

``natura explain TAG`` is :func:`explain`; ``tools/sections.py`` turns the pages into
``resources/sections.json`` (what the installed app reads, :mod:`app.teach.sections`).
"""

from __future__ import annotations

import html
import re
import textwrap
import unicodedata
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path

from .. import PROJECT_ROOT
from ..errors import UsageError, quote

THEORY = PROJECT_ROOT / "docs" / "theory"
#: where ``natura explain`` looks for the code that carries a tag
SOURCES = ("app", "glsl", "tests")
SUFFIXES = {".py", ".glsl", ".frag", ".vert", ".comp", ".geom", ".md", ".json", ".toml"}
#: a tag as the code writes it: ``spec/NNN eq. X`` or ``spec/NNN §X`` (a sub-letter after a
#: space, ``§2.9 a``; :func:`parse_tag` also takes ``§2.9(a)``)
TAG = re.compile(r"spec/(\d{3}) (?:eq\. ((?:[A-Z]\.)?\d+(?:\.\d+)?)"
                 r"|§ ?((?:[A-Z]|\d+)(?:\.(?:[A-Z]|\d+))*(?: [a-z]\b)?))")
ANCHOR = re.compile(r'^<a id="([^"]+)"></a>\s*$')
HEADING = re.compile(r"^(#{1,6})\s+(.*?)\s*#*\s*$")


GREEK = {
    "alpha": "α", "beta": "β", "gamma": "γ", "delta": "δ", "epsilon": "ϵ", "varepsilon": "ε",
    "zeta": "ζ", "eta": "η", "theta": "θ", "vartheta": "ϑ", "iota": "ι", "kappa": "κ",
    "lambda": "λ", "mu": "μ", "nu": "ν", "xi": "ξ", "pi": "π", "varpi": "ϖ", "rho": "ρ",
    "varrho": "ϱ", "sigma": "σ", "varsigma": "ς", "tau": "τ", "upsilon": "υ", "phi": "ϕ",
    "varphi": "φ", "chi": "χ", "psi": "ψ", "omega": "ω", "Gamma": "Γ", "Delta": "Δ",
    "Theta": "Θ", "Lambda": "Λ", "Xi": "Ξ", "Pi": "Π", "Sigma": "Σ", "Upsilon": "Υ",
    "Phi": "Φ", "Psi": "Ψ", "Omega": "Ω",
}
SYMBOLS = {
    "cdot": "·", "times": "×", "div": "÷", "pm": "±", "mp": "∓", "le": "≤", "leq": "≤",
    "ge": "≥", "geq": "≥", "ne": "≠", "neq": "≠", "approx": "≈", "sim": "∼", "simeq": "≃",
    "equiv": "≡", "propto": "∝", "ll": "≪", "gg": "≫", "infty": "∞", "partial": "∂",
    "nabla": "∇", "sum": "∑", "prod": "∏", "int": "∫", "oint": "∮", "to": "→",
    "rightarrow": "→", "leftarrow": "←", "Rightarrow": "⇒", "Leftarrow": "⇐",
    "leftrightarrow": "↔", "Leftrightarrow": "⇔", "mapsto": "↦", "in": "∈", "notin": "∉",
    "subset": "⊂", "cap": "∩", "cup": "∪", "emptyset": "∅", "forall": "∀", "exists": "∃",
    "circ": "∘", "odot": "⊙", "otimes": "⊗", "oplus": "⊕", "perp": "⊥", "parallel": "∥",
    "angle": "∠", "ldots": "…", "dots": "…", "cdots": "⋯", "vdots": "⋮", "ell": "ℓ",
    "imath": "ı", "jmath": "ȷ", "hbar": "ℏ", "deg": "°", "degree": "°", "prime": "′",
    "langle": "⟨", "rangle": "⟩", "lfloor": "⌊", "rfloor": "⌋", "lceil": "⌈", "rceil": "⌉",
    "lVert": "‖", "rVert": "‖", "Vert": "‖", "lvert": "|", "rvert": "|", "vert": "|",
    "|": "‖", "{": "{", "}": "}", "%": "%", "_": "_", "&": "&", "#": "#", "$": "$",
    "neg": "¬", "land": "∧", "lor": "∨", "star": "⋆", "ast": "∗", "bullet": "•",
    "uparrow": "↑", "downarrow": "↓", "setminus": "∖", "wedge": "∧", "vee": "∨",
}
SPACES = {",": " ", ";": " ", ":": " ", "!": "", " ": " ", "quad": "  ", "qquad": "    ",
          "enspace": " ", "thinspace": " "}
FUNCTIONS = {"sin", "cos", "tan", "cot", "sec", "csc", "arcsin", "arccos", "arctan", "sinh",
             "cosh", "tanh", "exp", "log", "ln", "lg", "max", "min", "sup", "inf", "lim",
             "det", "arg", "sgn", "dim", "ker", "gcd", "Pr"}
#: commands whose argument is shown as it is (the style is lost: plain text has none)
STYLES = {"text", "textrm", "textit", "textbf", "texttt", "textsf", "mathrm", "mathbf",
          "mathit", "mathsf", "mathtt", "mathcal", "boldsymbol", "bm", "mbox", "operatorname",
          "mathbb", "mathfrak", "emph", "displaystyle", "textstyle"}
BLACKBOARD = {"R": "ℝ", "N": "ℕ", "Z": "ℤ", "Q": "ℚ", "C": "ℂ"}
ACCENTS = {"hat": "\u0302", "widehat": "\u0302", "bar": "\u0304", "overline": "\u0305",
           "tilde": "\u0303", "widetilde": "\u0303", "vec": "\u20d7", "dot": "\u0307",
           "ddot": "\u0308", "check": "\u030c", "acute": "\u0301", "grave": "\u0300"}
SIZES = {"left", "right", "big", "Big", "bigg", "Bigg", "bigl", "bigr", "Bigl", "Bigr",
         "biggl", "biggr", "Biggl", "Biggr", "middle", "limits", "nolimits"}
SUP = dict(zip("0123456789+-−=()niabcdefghjklmoprstuvwxyzABDEGHIJKLMNOPRTUVWβγδθφχ′'*∘°",
               "⁰¹²³⁴⁵⁶⁷⁸⁹⁺⁻⁻⁼⁽⁾ⁿⁱᵃᵇᶜᵈᵉᶠᵍʰʲᵏˡᵐᵒᵖʳˢᵗᵘᵛʷˣʸᶻᴬᴮᴰᴱᴳᴴᴵᴶᴷᴸᴹᴺᴼᴾᴿᵀᵁⱽᵂᵝᵞᵟᶿᵠᵡ′′*°°"))
SUB = dict(zip("0123456789+-−=()aehijklmnoprstuvxβγρφχ",
               "₀₁₂₃₄₅₆₇₈₉₊₋₋₌₍₎ₐₑₕᵢⱼₖₗₘₙₒₚᵣₛₜᵤᵥₓᵦᵧᵨᵩᵪ"))
RELATIONS = set("=<>≤≥≠≈∼≃≡∝≪≫→←⇒⇐↔⇔↦∈∉⊂")
OPERATORS = set("+−·×÷±∓∘⊙⊗⊕/∧∨")

#: TeX commands the converter met and does not know (shown without their backslash); a test
#: keeps this empty over every page
UNKNOWN: set[str] = set()

_TEX_TOKEN = re.compile(r"\\([A-Za-z]+)|\\(.)|(\s+)|(.)", re.S)


@dataclass
class _Atom:
    kind: str   # ord, op, rel, open, close, punct, space, frac, func
    text: str


class _Tex:
    """A small recursive reader of the TeX the pages use in their math."""

    def __init__(self, tex: str):
        self.tokens: list[tuple[str, str]] = []
        for m in _TEX_TOKEN.finditer(tex):
            if m.group(1) is not None:
                self.tokens.append(("cmd", m.group(1)))
            elif m.group(2) is not None:
                self.tokens.append(("cmd", m.group(2)))
            elif m.group(3) is not None:
                self.tokens.append(("space", " "))
            else:
                self.tokens.append(("char", m.group(4)))
        self.i = 0

    def peek(self) -> tuple[str, str] | None:
        return self.tokens[self.i] if self.i < len(self.tokens) else None

    def skip_spaces(self) -> None:
        while (t := self.peek()) is not None and t[0] == "space":
            self.i += 1

    def argument(self) -> list[_Atom]:
        """The next argument: a ``{…}`` group or one token."""
        self.skip_spaces()
        t = self.peek()
        if t is None:
            return []
        if t == ("char", "{"):
            self.i += 1
            return self.sequence(stop="}")
        self.i += 1
        return self.token(t)

    def raw_argument(self) -> str:
        """A ``{…}`` argument as its source text (``\\text{…}``, ``\\begin{…}``)."""
        self.skip_spaces()
        t = self.peek()
        if t is None:
            return ""
        self.i += 1
        if t != ("char", "{"):
            return t[1]
        depth, out = 1, []
        while (t := self.peek()) is not None:
            self.i += 1
            if t == ("char", "{"):
                depth += 1
            elif t == ("char", "}"):
                depth -= 1
                if not depth:
                    break
            out.append(t[1] if t[0] != "cmd" else "\\" + t[1])
        return "".join(out)

    def sequence(self, stop: str | None = None, env: str | None = None) -> list[_Atom]:
        atoms: list[_Atom] = []
        while (t := self.peek()) is not None:
            if stop is not None and t == ("char", stop):
                self.i += 1
                break
            if env is not None and t == ("cmd", "end"):
                self.i += 1
                self.raw_argument()
                break
            self.i += 1
            if t in (("char", "^"), ("char", "_")):
                arg = render(self.argument())
                base = atoms.pop() if atoms and atoms[-1].kind != "space" else _Atom("ord", "")
                atoms.append(_Atom(base.kind if base.kind in ("func", "op", "close") else "ord",
                                   base.text + script(arg, t[1] == "^")))
                continue
            atoms += self.token(t)
        return atoms

    def token(self, t: tuple[str, str]) -> list[_Atom]:
        kind, value = t
        if kind == "space":
            return [_Atom("space", " ")]
        if kind == "char":
            if value == "{":
                return [_Atom("ord", render(self.sequence(stop="}")))]
            if value == "-":
                return [_Atom("op", "−")]
            if value in "+*/":
                return [_Atom("op", value)]
            if value in "=<>":
                return [_Atom("rel", value)]
            if value in "([":
                return [_Atom("open", value)]
            if value in ")]":
                return [_Atom("close", value)]
            if value in ",;:!?.":
                return [_Atom("punct", value)]
            if value == "~":
                return [_Atom("space", " ")]
            if value == "'":
                return [_Atom("ord", "′")]
            if value == "&":
                return [_Atom("cell", "")]
            return [_Atom("ord", value)]
        return self.command(value)

    def command(self, name: str) -> list[_Atom]:
        if name in GREEK or SYMBOLS.get(name) in ("∂", "∇"):
            # "\\omega t" is ωt, "\\partial x" ∂x: the space ends the command's name
            if (self.peek() == ("space", " ") and self.i + 1 < len(self.tokens)
                    and self.tokens[self.i + 1][0] == "char"
                    and self.tokens[self.i + 1][1].isalnum()):
                self.i += 1
            return [_Atom("ord", GREEK.get(name) or SYMBOLS[name])]
        if name in SPACES:
            return [_Atom("space", SPACES[name])] if SPACES[name] else []
        if name in SIZES:
            self.skip_spaces()
            t = self.peek()
            if name in ("left", "right", "middle") and t is not None:
                self.i += 1
                if t == ("char", "."):
                    return []
                atom = self.token(t)
                kind = "open" if name == "left" else "close" if name == "right" else "ord"
                return [_Atom(kind, a.text) for a in atom]
            return []
        if name in ("frac", "dfrac", "tfrac", "cfrac"):
            num, den = render(self.argument()), render(self.argument())
            return [_Atom("frac", f"{_wrap_num(num)}/{_wrap_den(den)}")]
        if name == "sqrt":
            self.skip_spaces()
            index = ""
            if self.peek() == ("char", "["):
                self.i += 1
                index = render(self.sequence(stop="]"))
            body = render(self.argument())
            root = {"": "√", "2": "√", "3": "∛", "4": "∜"}.get(index)
            if root is None:
                root = script(index, True) + "√"
            return [_Atom("ord", root + (body if _simple(body) else f"({body})"))]
        if name in STYLES:
            if name in ("text", "textrm", "textit", "textbf", "texttt", "textsf", "mbox",
                        "emph"):
                return [_Atom("ord", self.raw_argument())]
            if name in ("displaystyle", "textstyle"):
                return []
            inner = render(self.argument())
            if name == "mathbb":
                inner = "".join(BLACKBOARD.get(c, c) for c in inner)
            return [_Atom("func" if name == "operatorname" else "ord", inner)]
        if name in ACCENTS:
            inner = render(self.argument())
            mark = ACCENTS[name]
            if len(inner) == 1:
                return [_Atom("ord", unicodedata.normalize("NFC", inner + mark))]
            if name == "overline" and inner.isalnum():
                return [_Atom("ord", "".join(c + mark for c in inner))]
            return [_Atom("ord", f"‾({inner})" if name == "overline" else f"{inner}{mark}")]
        if name in FUNCTIONS:
            return [_Atom("func", name)]
        if name in ("bmod", "mod"):
            return [_Atom("op", "mod")]
        if name == "pmod":
            return [_Atom("ord", f"(mod {render(self.argument())})")]
        if name == "begin":
            return self.environment(self.raw_argument())
        if name == "\\":
            return [_Atom("row", "")]
        if name in SYMBOLS:
            s = SYMBOLS[name]
            if s in RELATIONS:
                return [_Atom("rel", s)]
            if s in OPERATORS:
                return [_Atom("op", s)]
            if s in "⟨⌊⌈":
                return [_Atom("open", s)]
            if s in "⟩⌋⌉":
                return [_Atom("close", s)]
            return [_Atom("ord", s)]
        UNKNOWN.add(name)
        return [_Atom("ord", name)]

    def environment(self, name: str) -> list[_Atom]:
        """``pmatrix`` and friends as ``(a, b, c)`` (a column) or ``(a b; c d)``; ``cases``
        as ``{a if …; b otherwise}``; ``aligned`` as its rows separated by ``;``."""
        if name == "array":
            self.raw_argument()  # the column spec
        atoms = self.sequence(env=name)
        rows: list[list[str]] = [[]]
        cell: list[_Atom] = []
        for a in atoms + [_Atom("row", "")]:
            if a.kind in ("cell", "row"):
                rows[-1].append(render(cell))
                cell = []
                if a.kind == "row":
                    rows.append([])
            else:
                cell.append(a)
        rows = [r for r in rows if any(c for c in r)]
        if name == "cases":
            parts = []
            for r in rows:
                value, cond = r[0], " ".join(c for c in r[1:] if c)
                parts.append(f"{value}, {cond}" if cond else value)
            return [_Atom("ord", "{" + "; ".join(parts) + "}")]
        if all(len(r) == 1 for r in rows):
            body = ", ".join(r[0] for r in rows)
        else:
            body = "; ".join(" ".join(c for c in r) for r in rows)
        brackets = {"pmatrix": "()", "bmatrix": "[]", "vmatrix": "||", "Vmatrix": "‖‖",
                    "Bmatrix": "{}"}.get(name)
        if brackets is None:
            return [_Atom("ord", body)]
        return [_Atom("ord", brackets[0] + body + brackets[1])]


def _top_level(text: str) -> str:
    """``text`` without what is inside its brackets."""
    out, depth = [], 0
    for c in text:
        if c in "([{⟨⌊⌈":
            depth += 1
        elif c in ")]}⟩⌋⌉" and depth:
            depth -= 1
        elif not depth:
            out.append(c)
    return "".join(out)


def _simple(text: str) -> bool:
    """One symbol (with its scripts), a number, or something already bracketed."""
    if re.fullmatch(r"[−-]?\d+(?:\.\d+)?|[∂∇√]?\w[\u0300-\u036f\u20d7]?[^\s\w()/+−=·×]*",
                    text):
        return True
    return bool(re.fullmatch(r"\(.*\)", text)) and _top_level(text) == ""


def _wrap_num(text: str) -> str:
    top = _top_level(text)
    return f"({text})" if any(c in top for c in " +−-=·×/<>≤≥,") else text


def _wrap_den(text: str) -> str:
    return text if _simple(text) else f"({text})"


def script(text: str, sup: bool) -> str:
    """``text`` as a superscript (``sup``) or subscript: Unicode's raised or lowered characters
    when it has one for every character, else ``^x`` / ``^(…)``."""
    text = text.strip()
    table = SUP if sup else SUB
    if text and all(c in table for c in text):
        return "".join(table[c] for c in text)
    mark = "^" if sup else "_"
    return mark + (text if _simple(text) and len(text) == 1 else f"({text})")


def render(atoms: list[_Atom]) -> str:
    """Atoms as text: a fraction multiplied by its neighbour is set off by " · " (after a
    function name it is bracketed), a function name is set off from a letter before or after
    it, spaces collapse."""
    out: list[str] = []
    # a wide space (\\quad) separates; a narrow one does not
    solid = [a for a in atoms if a.kind != "space" or len(a.text) > 1]
    for n, a in enumerate(atoms):
        text = a.text
        if a.kind == "frac" and len(solid) > 1:
            k = next(j for j, b in enumerate(solid) if b is a)
            before = solid[k - 1].kind if k else "rel"
            after = solid[k + 1].kind if k + 1 < len(solid) else "rel"
            if before == "func":
                text = f"({text})"
            elif before in ("ord", "frac", "close"):
                text = " · " + text
            if after in ("ord", "frac", "open", "func") and before != "func":
                text += " · "
        if a.kind == "func":
            prev = out[-1][-1:] if out else ""
            if prev and (prev.isalnum() or prev in "′)"):
                text = " " + text
            nxt = next((b for b in atoms[n + 1:]), None)
            if nxt is not None and nxt.kind == "ord" and not a.text.endswith(")"):
                text += " "
        if a.kind == "op" and a.text == "mod":
            text = " mod "
        elif (a.kind == "rel" and a.text not in "<>=") or a.text == "×":
            text = f" {text} "  # spaced as TeX sets them (=, <, > keep the page's spacing)
        out.append(text)
    s = "".join(out)
    s = re.sub(r" *· +· *| {1,3}· {1,3}", " · ", s)
    s = re.sub(r"[ \t]{2,}(?=\S)", lambda m: m.group() if len(m.group()) >= 4 else " ", s)
    return s.strip()


def tex_to_unicode(tex: str) -> str:
    """One piece of TeX math as readable Unicode: ``\\frac{1}{4\\pi}`` → ``1/(4π)``,
    ``x^{2}`` → ``x²``, ``\\sqrt{a+b}`` → ``√(a+b)``, ``\\cos\\theta`` → ``cos θ``."""
    reader = _Tex(tex)
    return render(reader.sequence())


#: math in a body: ``$$…$$`` (a display, one line) or ``$…$``; ``\\$`` is a dollar sign
MATH = re.compile(r"\$\$(.+?)\$\$|(?<!\\)\$((?:[^$\\\n]|\\.)+?)\$")


def math_to_unicode(text: str) -> str:
    """A body as shown in a terminal or the panel: its math as Unicode (a display on a line
    of its own, indented), ``\\$`` as ``$``."""
    def one(m: re.Match) -> str:
        if m.group(1) is not None:
            return "    " + tex_to_unicode(m.group(1))
        return tex_to_unicode(m.group(2))
    return MATH.sub(one, text).replace("\\$", "$")


def math_to_html(text: str) -> str:
    """A body as HTML: text escaped, math as MathML (``latex2mathml``), Unicode where the
    converter refuses a formula."""
    import latex2mathml.converter as l2m

    out, pos = [], 0
    for m in MATH.finditer(text):
        out.append(html.escape(text[pos:m.start()].replace("\\$", "$"), quote=True))
        display = m.group(1) is not None
        tex = m.group(1) if display else m.group(2)
        try:
            out.append(l2m.convert(tex, display="block" if display else "inline"))
        except Exception:  # noqa: BLE001 — a formula it cannot read: the Unicode text
            out.append(html.escape(tex_to_unicode(tex), quote=True))
        pos = m.end()
    out.append(html.escape(text[pos:].replace("\\$", "$"), quote=True))
    return "".join(out)


_SPANS = re.compile(r"`+[^`]*?`+|\$\$.+?\$\$|(?<!\\)\$(?:[^$\\\n]|\\.)+?\$")


def _inline(text: str) -> str:
    """One line of markdown as plain text: math and code spans kept apart (a ``$`` in code is
    ``\\$``), bold, italics, links and escapes removed."""
    kept: list[str] = []

    def keep(m: re.Match) -> str:
        s = m.group()
        if s.startswith("`"):
            s = s.strip("`").replace("$", "\\$")
        kept.append(s)
        return f"\0{len(kept) - 1}\0"

    text = _SPANS.sub(keep, text)
    text = re.sub(r"!\[([^\]]*)\]\([^)]*\)", r"[figure: \1]", text)
    text = re.sub(r"\[([^\]]+)\]\((?:[^()]|\([^)]*\))*\)", r"\1", text)  # [text](url)
    text = re.sub(r"<a id=\"[^\"]*\"></a>", "", text)
    text = re.sub(r"\*\*(.+?)\*\*", r"\1", text)
    text = re.sub(r"(?<![\w*])\*(?=\S)(.+?)(?<=\S)\*(?![\w*])", r"\1", text)
    text = re.sub(r"(?<!\w)_(?=\S)(.+?)(?<=\S)_(?!\w)", r"\1", text)
    text = re.sub(r"\\([_\[\]()#<>|*`])", r"\1", text)
    return re.sub(r"\0(\d+)\0", lambda m: kept[int(m.group(1))], text)


def _paragraphs(lines: list[str]) -> list[str]:
    """The page's lines with each paragraph (and each bullet with its continuation lines) on
    one line, so that a code span, bold text or math broken over two lines reads whole; code
    blocks, displays, tables and headings are kept as they are."""
    out: list[str] = []
    code = display = cont = False
    for raw in lines:
        line = raw.rstrip()
        s = line.strip()
        if code:
            out.append(line)
            code = not s.startswith("```")
            continue
        if display:
            out.append(line)
            display = "$$" not in s
            continue
        if s.startswith("```"):
            out.append(line)
            code, cont = True, False
            continue
        if s.count("$$") % 2 == 1:
            out.append(line)
            display, cont = True, False
            continue
        if (not s or HEADING.match(s) or ANCHOR.match(s) or s.startswith(("|", "$$"))
                or re.fullmatch(r"-{3,}|\*{3,}|_{3,}", s)):
            out.append(line)
            cont = False
            continue
        if re.match(r"^\s*(?:[-*+]|\d+\.)\s+", line):
            out.append(line)
            cont = True
            continue
        if cont:
            out[-1] += " " + s
            continue
        out.append(line)
        cont = True
    return out


def strip_markdown(lines: list[str]) -> str:
    """Lines of a page as a body: bullets as "•", tables as "a · b" rows, code blocks
    indented, headings as their text, display math on one line, rules and runs of blank lines
    dropped."""
    out: list[str] = []
    code = False
    display: list[str] | None = None
    for raw in _paragraphs(lines):
        line = raw.rstrip()
        if display is not None:  # inside a $$ … $$ over several lines
            if "$$" in line:
                head, tail = line.split("$$", 1)
                display.append(head.strip())
                out.append("$$" + " ".join(x for x in display if x) + "$$")
                display = None
                if tail.strip():
                    out.append(_inline(tail.strip()))
            else:
                display.append(line.strip())
            continue
        if line.lstrip().startswith("```"):
            code = not code
            continue
        if code:
            out.append("    " + line)
            continue
        stripped = line.strip()
        if stripped.count("$$") % 2 == 1:  # a display opens here
            head, rest = stripped.split("$$", 1)
            if head.strip():
                out.append(_inline(head.strip()))
            display = [rest.strip()]
            continue
        if ANCHOR.match(stripped) or re.fullmatch(r"-{3,}|\*{3,}|_{3,}", stripped):
            continue
        h = HEADING.match(stripped)
        if h:
            out += ["", _inline(h.group(2)), ""]
            continue
        if stripped.startswith("|"):
            cells = [c.strip() for c in re.split(r"(?<!\\)\|", stripped.strip("|"))]
            if all(re.fullmatch(r":?-{2,}:?", c) for c in cells if c):
                continue
            out.append(" · ".join(_inline(c) for c in cells))
            continue
        m = re.match(r"^(\s*)(?:[-*+]|\d+\.)\s+(.*)$", line)
        if m:
            depth = len(m.group(1).expandtabs(4)) // 2
            out.append("  " * depth + "• " + _inline(m.group(2)))
            continue
        if stripped.startswith(">"):
            stripped = stripped.lstrip("> ")
        out.append(_inline(stripped) if stripped else "")
    text = "\n".join(out)
    text = re.sub(r"\n{3,}", "\n\n", text)
    return text.strip("\n")


@dataclass
class Entry:
    """One anchored section of a page."""

    spec: str       # "spec/003"
    anchor: str     # "s-2.9-a", "eq-7.18"
    level: int      # its heading's level (2 for ##)
    heading: str    # the heading as written, markdown stripped: "§2.9 a Geometry-shader grass"
    line: int       # the heading's line (1-based)
    end: int        # the line after the section (the next anchor or heading of its level)
    own_end: int    # the line after its own text (the next anchor or heading of any level)
    body: str = ""  # its own text (math as $TeX$)

    @property
    def ref(self) -> str:
        """``"spec/003 §2.9(a)"`` or ``"spec/003 eq. 7.18"`` (the panel's form)."""
        return f"{self.spec} {anchor_number(self.anchor)}"

    @property
    def tag(self) -> str:
        """``"spec/003 §2.9 a"``: the form the code writes."""
        return f"{self.spec} {anchor_tag(self.anchor)}"

    @property
    def title(self) -> str:
        """The heading without its number: "Geometry-shader grass (rejected by the thesis)"."""
        return split_heading(self.heading)[0]

    @property
    def source(self) -> str:
        return split_heading(self.heading)[1]


@dataclass
class Page:
    spec: str
    path: Path
    heading: str                    # the page's title (its # heading)
    title: str                      # the thesis's own title, from the citation
    citation: str                   # the citation paragraph, plain
    lines: list[str] = field(repr=False, default_factory=list)
    entries: dict[str, Entry] = field(default_factory=dict)


def anchor_number(anchor: str) -> str:
    """``"s-2.9-a"`` → ``"§2.9(a)"``; ``"eq-7.18"`` → the number of ``spec/003 eq. 7.18``."""
    if anchor.startswith("eq-"):
        return "eq. " + anchor[3:]
    number = anchor[2:]
    if re.search(r"-[a-z]$", number):
        number = f"{number[:-2]}({number[-1]})"
    return "§" + number


def anchor_tag(anchor: str) -> str:
    """``"s-2.9-a"`` → ``"§2.9 a"`` (the code's form)."""
    if anchor.startswith("eq-"):
        return "eq. " + anchor[3:]
    return "§" + anchor[2:].replace("-", " ")


def split_heading(heading: str) -> tuple[str, str]:
    """A heading's title and its note on the thesis's numbering: "§2.9 Grass (thesis §7.1)"
    → ("Grass", "thesis §7.1"); an equation's heading (number, dash, title) → (its title, "")."""
    text = re.sub(r"^(?:§\s?[\w.]+(?:\s[a-z](?=\s)|\([a-z]\))?|Eq\.\s?[\w.]+)\s*[—–:-]?\s*", "",
                  heading.strip())
    source = ""
    m = re.search(r"\s*\(((?:thesis|the thesis's)\b[^()]*)\)\s*$", text)
    if m:
        source, text = m.group(1), text[:m.start()]
    return (text.strip() or heading.strip()), source


def parse_page(path: Path) -> Page:
    """One theory page: its title, citation and anchored sections."""
    lines = path.read_text(encoding="utf-8").splitlines()
    spec = f"spec/{path.name[:3]}"
    heading = ""
    headings: list[tuple[int, int]] = []  # (line index, level) outside code blocks
    code = False
    for i, line in enumerate(lines):
        if line.lstrip().startswith("```"):
            code = not code
            continue
        h = HEADING.match(line) if not code else None
        if h:
            headings.append((i, len(h.group(1))))
            if len(h.group(1)) == 1 and not heading:
                heading = _inline(h.group(2))
    cite = next((i for i, line in enumerate(lines) if line.startswith("**Citation.**")), None)
    citation, title = "", heading
    if cite is not None:
        end = next((i for i in range(cite, len(lines)) if not lines[i].strip()), len(lines))
        raw = " ".join(x.strip() for x in lines[cite:end])
        m = re.search(r"(?<![\w*])\*([^*]+)\*", raw.replace("**Citation.**", ""))
        if m and len(m.group(1).split()) >= 3:  # a title, not a word in italics
            title = m.group(1).strip()
        citation = math_to_unicode(_inline(raw.replace("**Citation.**", "").strip()))
    page = Page(spec, path, heading, title, citation, lines)
    pending: list[str] = []
    for i, line in enumerate(lines):
        m = ANCHOR.match(line.strip())
        if m:
            pending.append(m.group(1))
            continue
        h = HEADING.match(line)
        if pending and h:
            level = len(h.group(1))
            after = [(j, lv) for j, lv in headings if j > i]
            end = next((j for j, lv in after if lv <= level), len(lines))
            own = next((j for j, lv in after), len(lines))
            for a in pending:
                page.entries[a] = Entry(spec, a, level, _inline(h.group(2)), i + 1,
                                        _before_anchors(lines, end), _before_anchors(lines, own))
        pending = [] if line.strip() else pending
    for e in page.entries.values():
        e.body = strip_markdown(lines[e.line:e.own_end - 1])
    return page


def _before_anchors(lines: list[str], end: int) -> int:
    """The 1-based line after a section that ends before heading index ``end``: the anchors
    right before that heading belong to the next section."""
    while end > 0 and ANCHOR.match(lines[end - 1].strip() or "-"):
        end -= 1
    return end + 1


@cache
def pages(root: Path = THEORY) -> dict[str, Page]:
    """Every page under ``root`` by its spec (``"spec/003"``)."""
    return {f"spec/{p.name[:3]}": parse_page(p) for p in sorted(root.glob("[0-9][0-9][0-9]-*.md"))}


def section_body(page: Page, entry: Entry) -> str:
    """The whole section of ``entry``: its text and every deeper section inside it, their
    headings included (math as $TeX$)."""
    return strip_markdown(page.lines[entry.line:entry.end - 1])


def anchor_of(eq: str | None, section: str | None) -> str:
    if eq:
        return f"eq-{eq}"
    assert section is not None
    return "s-" + section.rstrip(".").replace(" ", "-")


ALLOWED = 'allowed spec/NNN eq. X or spec/NNN §X, e.g. "spec/003 eq. 7.18" or "spec/003 §2.9 a"'


def parse_tag(text: str) -> tuple[str, str]:
    """``"spec/003 §2.9 a"`` (or ``§2.9(a)``; ``spec/003 eq. 7.18``) → (``"spec/003"``, the anchor);
    anything else is a :class:`UsageError` naming it and the forms allowed."""
    s = " ".join(text.split())
    s = re.sub(r"§\s?([\w.]+)\(([a-z])\)$", r"§\1 \2", s)
    s = re.sub(r"\beq\.?\s?(?=[A-Z0-9])", "eq. ", s)
    m = TAG.fullmatch(s)
    if not m:
        raise UsageError(f"{quote(text)} is not an equation or section tag: {ALLOWED}")
    return f"spec/{m.group(1)}", anchor_of(m.group(2), m.group(3))


def find(text: str, root: Path = THEORY) -> tuple[Page, Entry]:
    """The page and section a tag names; an unknown one is a :class:`UsageError`."""
    spec, anchor = parse_tag(text)
    found = pages(root)
    if spec not in found:
        have = ", ".join(sorted(found)) or "none"
        raise UsageError(f"{quote(text)}: no theory page for {spec}: allowed {have}")
    page = found[spec]
    if anchor not in page.entries:
        kind = [e for e in page.entries.values() if e.anchor[:2] == anchor[:2]]
        span = f"{kind[0].tag.split(' ', 1)[1]} … {kind[-1].tag.split(' ', 1)[1]}" if kind else ""
        raise UsageError(f"{quote(text)}: {page.path.name} has no {anchor_number(anchor)}: "
                         f"allowed one it has ({len(kind)}: {span})")
    return page, page.entries[anchor]


#: files that hold tags as data, not as citations (the recorded test ids)
NOT_CITATIONS = {"durations.json"}


def scan(root: Path = PROJECT_ROOT, tops: tuple[str, ...] = SOURCES):
    """(path relative to ``root``, line, spec, anchor) of every tag in ``tops``."""
    for top in tops:
        for path in sorted((root / top).rglob("*")):
            if (path.suffix not in SUFFIXES or "__pycache__" in path.parts
                    or path.name in NOT_CITATIONS or not path.is_file()):
                continue
            try:
                text = path.read_text(encoding="utf-8")
            except (OSError, UnicodeDecodeError):
                continue
            if "spec/" not in text:
                continue
            for i, line in enumerate(text.splitlines(), 1):
                for m in TAG.finditer(line):
                    yield (path.relative_to(root).as_posix(), i, f"spec/{m.group(1)}",
                           anchor_of(m.group(2), m.group(3)))


#: files whose tags are examples of the form, not citations
EXAMPLES = {"app/teach/theory.py", "app/teach/sections.py", "app/cli.py"}
#: how :func:`explain` names each kind of file that carries a tag
KINDS = (("GLSL", ("glsl/",)), ("numpy twin", ("app/sim/",)), ("Python", ("app/",)),
         ("tests", ("tests/",)))


def uses(spec: str, anchor: str, root: Path = PROJECT_ROOT) -> dict[str, list[str]]:
    """Every ``file:line`` under app/, glsl/ and tests/ that carries the tag, by kind."""
    out: dict[str, list[str]] = {k: [] for k, _ in KINDS}
    for path, line, s, a in scan(root):
        if (s, a) != (spec, anchor) or path in EXAMPLES:
            continue
        kind = next(k for k, prefixes in KINDS if path.startswith(prefixes))
        where = f"{path}:{line}"
        if where not in out[kind]:
            out[kind].append(where)
    return out


def wrap(line: str, width: int = 100) -> str:
    """One line of a body folded at ``width`` columns, a bullet's lines under its text; code
    and displays (indented four spaces) are left as they are."""
    if len(line) <= width or line.startswith("    "):
        return line
    m = re.match(r"^(\s*(?:• )?)", line)
    indent = " " * len(m.group(1)) if m else ""
    return textwrap.fill(line, width, subsequent_indent=indent, break_long_words=False,
                         break_on_hyphens=False)


def explain(text: str, root: Path = PROJECT_ROOT) -> str:
    """What ``natura explain TAG`` prints: the section's heading and text, its math as
    Unicode, then every file:line that carries the tag."""
    page, entry = find(text, root / "docs" / "theory")
    rel = page.path.relative_to(root).as_posix() if page.path.is_relative_to(root) else page.path
    head = f"{entry.tag} — {entry.title}"
    lines = [head, "=" * min(len(head), 100),
             f"{page.title} ({rel}:{entry.line}, #{entry.anchor})", ""]
    lines += [wrap(line) for line in math_to_unicode(section_body(page, entry)).splitlines()]
    found = uses(page.spec, entry.anchor, root)
    total = sum(len(v) for v in found.values())
    lines += ["", f"Where the code carries {entry.tag} ({total} place{'s' * (total != 1)}):"]
    for kind, where in found.items():
        lines.append(f"  {kind}:" + ("" if where else " none"))
        lines += [f"    {w}" for w in where]
    return "\n".join(lines)

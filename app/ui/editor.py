"""The window's shader editor (F2, or the panel's "Shader editor" button).

What a user sees is in docs/commands.md ("Teaching tools"). A typed bracket gets its closer,
and typing that closer steps over it (``type_chars``, at any frame rate: every character a slow
frame queued); a dialog opens only once the keys pressed before it was asked for have gone to
the text, which had the keyboard when they were pressed. A file changed on disk while open
reloads by itself when the editor holds no unsaved change, and otherwise asks.

The logic without ImGui (trees, markers, saving, the copy) is app/teach/editor.py.
"""

from __future__ import annotations

import contextlib
import time
from pathlib import Path
from typing import Callable

from imgui_bundle import imgui
from imgui_bundle import imgui_color_text_edit as ed

from ..errors import NaturaError
from ..teach import editor as logic
from . import panel

TextEditor = ed.TextEditor
#: how often the open file is compared with the disk (seconds)
DISK_CHECK_SECONDS = 0.5
MARKER_NUMBER_COLOUR = imgui.IM_COL32(255, 90, 80, 255)
MARKER_TEXT_COLOUR = imgui.IM_COL32(120, 30, 30, 160)
#: brackets the editor closes as they are typed (typing the closer then steps over it)
PAIRS = {"(": ")", "[": "]", "{": "}"}
#: an opener is closed only before these (or at the end of the line), as editors do
CLOSE_BEFORE = set(" \t;,.)]}")


class ShaderEditorPane:
    """One editor window; ``draw(library)`` once per frame while it is shown."""

    def __init__(self, say: Callable[[str], None], fail: Callable[[str], None], font=None):
        self.say, self.fail, self.font = say, fail, font
        self.shown = False
        self.editor = TextEditor()
        self.editor.set_language(TextEditor.Language.glsl())
        self.editor.set_show_line_numbers_enabled(True)
        self.editor.set_tab_size(4)
        self.editor.set_show_whitespaces_enabled(False)
        # brackets are paired here (type_chars): the widget's own pairing never types over its
        # closer, so typing `x(y)` gave `x(y))`
        self.editor.set_complete_paired_glyphs(False)
        self._closers: list[tuple[int, int]] = []  # (line, index) of closers typed for the user
        self._typed_state: tuple = ()  # the editor's (undo index, caret) after type_chars
        self._child_suffix = ""  # the text child's window name ends so (known after a draw)
        self.file: logic.OpenFile | None = None
        self.baseline = ""          # the editor's text as loaded or saved
        self.marked: dict[int, str] = {}
        self.copy_name = ""
        self.problem: str | None = None  # the last save's or open's problem, one line
        self._last_disk_check = 0.0
        self._ask_copy = False
        self._ask_conflict = False
        self.saves = 0
        self.text_rect = (0.0, 0.0, 0.0, 0.0)  # where the text was drawn (x0, y0, x1, y1)
        self._tree_key: tuple = ()
        self._tree_cache: list[logic.ProgramTree] = []
        self.modal_open = False
        self._ask_after = 0  # a dialog opens once the keys pressed before it was asked are out

    def open(self, path: Path) -> bool:
        try:
            f = logic.OpenFile.open(Path(path))
        except Exception as exc:  # noqa: BLE001 - unreadable: a line, not a crash
            self.problem = f"cannot open {path}: {exc}"
            self.fail(self.problem)
            return False
        self.file = f
        self.editor.set_text(f.text)
        self.baseline = self.editor.get_text()
        self.marked = {}
        self.editor.clear_markers()
        self.problem = None
        self.shown = True
        return True

    @property
    def modified(self) -> bool:
        return self.file is not None and self.editor.get_text() != self.baseline

    def _text_to_save(self) -> str:
        text = self.editor.get_text()
        return text if text.endswith("\n") else text + "\n"

    def save(self, library, overwrite: bool = False) -> bool:
        """Save the open file; inside Natura's own shaders, ask for a copy first."""
        if self.file is None:
            return False
        if logic.is_natura_own(library.root):
            self.copy_name = self.copy_name or logic.free_copy_name(Path.cwd())
            self._ask_copy = True
            self._ask_after = panel.next_event_id()
            return False
        try:
            logic.save(self.file, self._text_to_save(), overwrite_disk_change=overwrite)
        except NaturaError as exc:
            if "changed on disk" in str(exc):
                self._ask_conflict = True
                self._ask_after = panel.next_event_id()
            self.problem = str(exc)
            self.fail(f"not saved: {exc}")
            return False
        except OSError as exc:
            self.problem = f"{self.file.path}: {exc.strerror or exc}"
            self.fail(f"not saved: {self.problem}")
            return False
        self.baseline = self.editor.get_text()
        self.problem = None
        self.saves += 1
        self.say(f"saved {self.file.path}")
        return True

    def copy_and_save(self, library) -> bool:
        """The first save's answer: copy the shaders to ``copy_name``, move there, save."""
        assert self.file is not None
        old_root = library.root
        try:
            dest = logic.move_to_copy(library, self.copy_name)
        except NaturaError as exc:
            self.problem = str(exc)
            self.fail(f"no copy made: {exc}")
            return False
        self.say(f"copied the shaders to {dest}: the window now runs from it "
                 f"(natura --shaders {dest})")
        text = self.editor.get_text()
        self.file = logic.OpenFile.open(logic.relocate(self.file.path, old_root, library.root))
        self.editor.set_text(text)  # keeps the unsaved edit
        self._ask_copy = False
        return self.save(library)

    def reload_from_disk(self) -> None:
        if self.file is not None:
            self.open(self.file.path)

    def _check_disk(self) -> None:
        now = time.perf_counter()
        if self.file is None or now - self._last_disk_check < DISK_CHECK_SECONDS:
            return
        self._last_disk_check = now
        if self.file.changed_on_disk() and not self.modified:
            with contextlib.suppress(Exception):  # a vanished file stays open as it was
                self.reload_from_disk()

    def update_markers(self, library, errors) -> None:
        if self.file is None:
            return
        marks = logic.markers(errors, library, self.file.path)
        if marks == self.marked:
            return
        self.editor.clear_markers()
        for line, message in sorted(marks.items()):
            self.editor.add_marker(line, MARKER_NUMBER_COLOUR, MARKER_TEXT_COLOUR, message,
                                   message)
        self.marked = marks

    def _state(self) -> tuple:
        pos = self.editor.get_current_cursor_position()
        return self.editor.get_undo_index(), pos.line, pos.index

    def _has_keyboard(self) -> bool:
        """Whether the text child has the keyboard this frame (ImGui's focused window)."""
        nav = imgui.get_current_context().nav_window
        return bool(self._child_suffix) and nav is not None and nav.name.endswith(
            self._child_suffix)

    def type_chars(self) -> None:
        """The characters ImGui queued for this frame, typed into the text here (before the
        widget draws): an opener gets its closer after the caret, and typing that closer steps
        over it instead of adding another — however many characters a slow frame queued."""
        e = self.editor
        queue = imgui.get_io().input_queue_characters
        if queue.size() == 0 or not self._has_keyboard():
            return
        chars = [chr(c) for c in list(queue)]
        if (e.is_read_only_enabled() or e.is_overwrite_enabled()
                or e.get_number_of_cursors() != 1 or any(ord(c) < 32 or ord(c) == 127
                                                          for c in chars)):
            self._closers.clear()  # the widget types these itself
            return
        if self._state() != self._typed_state:
            self._closers.clear()  # the text or the caret moved since: those closers are text
        queue.clear()
        for char in chars:
            self._type_char(char)
        self._typed_state = self._state()

    def _type_char(self, char: str) -> None:
        e = self.editor
        pos = e.get_current_cursor_position()
        line, col = pos.line, pos.index
        if e.current_cursor_has_selection():
            self._closers.clear()
            e.replace_text_in_current_cursor(char)
            return
        after = e.get_line_text(line)[col:col + 1]
        if (line, col) in self._closers and after == char:  # step over the closer we typed
            self._closers.remove((line, col))
            e.set_cursor(TextEditor.DocPos(line, col + 1))
            return
        close = PAIRS.get(char) if (after == "" or after in CLOSE_BEFORE) else None
        text = char + (close or "")
        e.replace_text_in_current_cursor(text)
        self._closers = [(ln, c + len(text) if ln == line and c >= col else c)
                         for ln, c in self._closers]
        if close:
            e.set_cursor(TextEditor.DocPos(line, col + 1))
            self._closers.append((line, col + 1))

    def draw(self, library, errors, size: tuple[float, float]) -> None:
        if not self.shown:
            return
        self._check_disk()
        self.update_markers(library, errors)
        w, h = size
        ew, eh = min(880.0, max(w * 0.62, 300.0)), min(640.0, h - 20.0)
        imgui.set_next_window_pos((max(w - ew - 10.0, 10.0), 10.0), imgui.Cond_.first_use_ever)
        imgui.set_next_window_size((ew, eh), imgui.Cond_.first_use_ever)
        expanded, self.shown = imgui.begin("Shader editor###natura-editor", self.shown)
        if expanded:
            self._draw_tree(library, errors)
            imgui.same_line()
            imgui.begin_group()
            self._draw_file(library, errors)
            imgui.end_group()
        imgui.end()
        self._draw_modals(library)

    def _draw_tree(self, library, errors) -> None:
        bad = {e.file for e in errors}
        width = min(240.0, 0.3 * imgui.get_content_region_avail().x)
        imgui.begin_child("programs", (width, 0.0), imgui.ChildFlags_.resize_x
                          | imgui.ChildFlags_.borders)
        own = logic.is_natura_own(library.root)
        imgui.text_disabled("Natura's own shaders (a save makes a copy)" if own
                            else f"{library.root}")
        for tree in self._trees(library):
            label = tree.name + (f"  ({len(tree.errors)} error(s))" if tree.errors else "")
            if tree.errors:
                imgui.push_style_color(imgui.Col_.text, panel.ERROR_COLOUR)
            opened = imgui.tree_node(f"{label}##prog-{tree.name}")
            if tree.errors:
                imgui.pop_style_color()
            if opened:
                for node in tree.stages:
                    self._draw_node(node, bad, tree.name)
                imgui.tree_pop()
        imgui.end_child()

    def _trees(self, library) -> list[logic.ProgramTree]:
        """The include trees, read from the files again only when a program's include set
        (its watched files), its compile or its root changed — not every frame."""
        key = (library.root, tuple((p.name, p.generation, p.failed, len(p.errors),
                                    tuple(p.stamps)) for p in library.programs()))
        if key != self._tree_key:
            self._tree_key, self._tree_cache = key, logic.program_trees(library)
        return self._tree_cache

    def _draw_node(self, node: logic.Node, bad: set[str], prefix: str) -> None:
        name = Path(node.label).name
        flags = imgui.TreeNodeFlags_.span_avail_width | imgui.TreeNodeFlags_.open_on_arrow
        if not node.children:
            flags |= imgui.TreeNodeFlags_.leaf
        if self.file is not None and node.path == self.file.path.resolve():
            flags |= imgui.TreeNodeFlags_.selected
        if node.label in bad:
            imgui.push_style_color(imgui.Col_.text, panel.ERROR_COLOUR)
        opened = imgui.tree_node_ex(f"{name}##{prefix}/{node.label}", flags)
        if node.label in bad:
            imgui.pop_style_color()
        if imgui.is_item_clicked() and not imgui.is_item_toggled_open():
            self.open(node.path)
        if imgui.is_item_hovered():
            imgui.set_tooltip(node.label)
        if opened:
            for child in node.children:
                self._draw_node(child, bad, prefix)
            imgui.tree_pop()

    def _draw_file(self, library, errors) -> None:
        if self.file is None:
            imgui.text_wrapped("Pick a file on the left: a program's stage files and what they "
                               "#include. Saving recompiles every program that reads the file.")
            return
        label = library.display(self.file.path)
        imgui.text(label + ("  *" if self.modified else ""))
        imgui.same_line()
        if imgui.small_button("Save"):
            self.save(library)
        imgui.same_line()
        if imgui.small_button("Revert"):
            self.reload_from_disk()
        imgui.same_line()
        imgui.text_disabled("Ctrl+S saves · Ctrl+Z undoes · Ctrl+F finds")
        mine = [e for e in errors if e.file == label]
        others = len(errors) - len(mine)
        lines = [str(e) for e in mine]
        if self.problem:
            lines.append(self.problem)
        rows = min(len(lines), 6)
        below = rows * imgui.get_text_line_height_with_spacing() * 2.2 + (24 if others else 0)
        if self.font is not None:
            imgui.push_font(self.font, 0.0)
        self.type_chars()
        self.editor.render("##glsl", (0.0, -max(below, 1.0)))
        self._child_suffix = f"/##glsl_{imgui.get_item_id():08X}"
        self.text_rect = (*imgui.get_item_rect_min(), *imgui.get_item_rect_max())
        if self.font is not None:
            imgui.pop_font()
        focused = imgui.is_item_focused() or imgui.is_window_focused(
            imgui.FocusedFlags_.root_and_child_windows)
        io = imgui.get_io()
        if focused and io.key_ctrl and imgui.is_key_pressed(imgui.Key.s, False):
            self.save(library)
        if lines:
            imgui.begin_child("errors", (0.0, 0.0))
            panel.error_list(lines)
            imgui.end_child()
        if others:
            imgui.text_disabled(f"{others} error(s) in other files: see the tree or the panel")

    def _draw_modals(self, library) -> None:
        # keys pressed while the text had the keyboard go to the text, however slow the frames:
        # a dialog (and its focused field) opens only once ImGui has handed them all out
        held = panel.queued_before(self._ask_after)
        if self._ask_copy and not held:
            imgui.open_popup("Save into a copy###natura-copy")
            self._ask_copy = False
        if imgui.begin_popup_modal("Save into a copy###natura-copy", None,
                                   imgui.WindowFlags_.always_auto_resize)[0]:
            imgui.push_text_wrap_pos(460.0)
            imgui.text_wrapped("These are Natura's own shaders; they are never written. Your "
                               "edit goes into a copy of the whole folder (as `natura shaders "
                               "copy DIR` makes it) and the window runs from the copy from now "
                               "on, as `natura --shaders DIR` would.")
            imgui.pop_text_wrap_pos()
            self.modal_open = True
            if imgui.is_window_appearing():
                imgui.set_keyboard_focus_here()
            entered, self.copy_name = imgui.input_text(
                "folder##copy", self.copy_name, imgui.InputTextFlags_.enter_returns_true)
            if imgui.button("Copy and save") or entered:
                if self.copy_and_save(library):
                    imgui.close_current_popup()
                    self.modal_open = False
            imgui.same_line()
            if imgui.button("Cancel"):
                imgui.close_current_popup()
                self.modal_open = False
            if self.problem:
                panel.error_list([self.problem])
            imgui.end_popup()
        else:
            self.modal_open = False
        if self._ask_conflict and not held:
            imgui.open_popup("Changed on disk###natura-conflict")
            self._ask_conflict = False
        if imgui.begin_popup_modal("Changed on disk###natura-conflict", None,
                                   imgui.WindowFlags_.always_auto_resize)[0]:
            imgui.text("The file changed on disk since it was opened.")
            if imgui.button("Reload (lose my edit)"):
                self.reload_from_disk()
                imgui.close_current_popup()
            imgui.same_line()
            if imgui.button("Overwrite"):
                self.save(library, overwrite=True)
                imgui.close_current_popup()
            imgui.same_line()
            if imgui.button("Cancel"):
                imgui.close_current_popup()
            imgui.end_popup()

//! The keyboard shortcuts: one table, [`SHORTCUTS`], drives the key handling, the shortcut texts
//! in the menus and the Help menu.
//!
//! - README.md's controls table lists the mouse controls ([`MOUSE`]) and then exactly these rows,
//!   input and description alike (a test checks).
//! - Shortcuts with modifiers are consumed (so `Ctrl+R` never also presses `R`); plain keys act
//!   only without modifiers.
//! - Only rows marked `while_typing` act while a text field has the keyboard.

use eframe::egui::{self, Key, KeyboardShortcut, Modifiers};

/// What a shortcut does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Command {
    /// The standard views, one per key in the order of [`vbrain::camera::View::ALL`].
    Views,
    ResetCamera,
    ToggleFly,
    Deselect,
    Frame,
    ToggleTransparency,
    ToggleVisible,
    Isolate,
    ResetLayout,
    Redo,
    /// Redo's second shortcut (Ctrl+Y).
    RedoY,
    Undo,
    SaveAs,
    Save,
    NextStep,
    PreviousStep,
    Open,
    Export,
}

/// One row of the table: keys (any of them) with modifiers.
pub struct Shortcut {
    pub keys: &'static [Key],
    pub modifiers: Modifiers,
    /// Acts even while a text field has the keyboard.
    pub while_typing: bool,
    pub command: Command,
    /// The keys as README.md and the Help menu write them.
    pub input: &'static str,
    pub description: &'static str,
}

impl Shortcut {
    const fn new(keys: &'static [Key], command: Command, input: &'static str, description: &'static str) -> Self {
        Shortcut { keys, modifiers: Modifiers::NONE, while_typing: false, command, input, description }
    }

    const fn command(self) -> Self {
        Shortcut { modifiers: Modifiers::COMMAND, ..self }
    }

    const fn command_shift(self) -> Self {
        Shortcut { modifiers: Modifiers { shift: true, ..Modifiers::COMMAND }, ..self }
    }

    const fn while_typing(self) -> Self {
        Shortcut { while_typing: true, ..self }
    }

    /// The shortcut of the row's `i`-th key.
    pub fn keyboard_shortcut(&self, i: usize) -> Option<KeyboardShortcut> {
        self.keys.get(i).map(|&key| KeyboardShortcut::new(self.modifiers, key))
    }
}

/// The mouse controls (input, description), for README.md and the Help menu.
pub const MOUSE: [(&str, &str); 7] = [
    ("left drag", "orbit around the target"),
    ("right or middle drag", "pan"),
    ("wheel", "zoom toward the cursor"),
    ("click", "select the organ under the cursor (clicks pass through organs fainter than 50 %)"),
    ("double-click", "select and frame the organ in front, faded or not"),
    ("Ctrl+drag / Shift+drag / Ctrl+Shift+drag", "move / rotate / resize the selected organ"),
    ("Ctrl+wheel", "resize the selected organ"),
];

/// The keyboard shortcuts, in the order they are handled within a frame.
pub const SHORTCUTS: [Shortcut; 18] = {
    use Command::*;
    [
        Shortcut::new(
            &[Key::Num1, Key::Num2, Key::Num3, Key::Num4, Key::Num5, Key::Num6],
            Views,
            "1 2 3 4 5 6",
            "anterior, posterior, left, right, superior, inferior view",
        ),
        Shortcut::new(&[Key::R, Key::Home], ResetCamera, "R or Home", "reset the camera"),
        Shortcut::new(
            &[Key::G],
            ToggleFly,
            "G",
            "walk-through camera on/off: W/A/S/D move, Q/E down/up, drag looks around",
        ),
        Shortcut::new(&[Key::Escape], Deselect, "Esc", "close the open menu, else deselect"),
        Shortcut::new(&[Key::F], Frame, "F", "frame the selected organ"),
        Shortcut::new(&[Key::T], ToggleTransparency, "T", "toggle the selected organ's transparency"),
        Shortcut::new(&[Key::H], ToggleVisible, "H", "hide or show the selected organ"),
        Shortcut::new(&[Key::I], Isolate, "I", "isolate the selected organ"),
        Shortcut::new(
            &[Key::R],
            ResetLayout,
            "Ctrl+R",
            "reset the organ layout (visibility, opacity, colour, transforms)",
        )
        .command(),
        // Before Undo: Ctrl+Z also matches Ctrl+Shift+Z, so this one must be consumed first.
        Shortcut::new(&[Key::Z], Redo, "Ctrl+Shift+Z", "redo what was undone").command_shift(),
        Shortcut::new(&[Key::Y], RedoY, "Ctrl+Y", "redo (as Ctrl+Shift+Z)").command(),
        Shortcut::new(&[Key::Z], Undo, "Ctrl+Z", "undo the last change to the organs (the Edit menu names it)")
            .command(),
        Shortcut::new(&[Key::S], SaveAs, "Ctrl+Shift+S", "save the scene in a new file").command_shift().while_typing(),
        Shortcut::new(&[Key::S], Save, "Ctrl+S", "save the scene (organs, camera, render settings) as a .vbscene file")
            .command()
            .while_typing(),
        Shortcut::new(&[Key::PageDown], NextStep, "PageDown", "next step of the open lesson"),
        Shortcut::new(&[Key::PageUp], PreviousStep, "PageUp", "previous step of the open lesson"),
        Shortcut::new(&[Key::O], Open, "Ctrl+O", "open an organ set or a scene").command().while_typing(),
        Shortcut::new(&[Key::E], Export, "Ctrl+E", "export a screenshot").command().while_typing(),
    ]
};

/// The row of a command.
pub fn find(command: Command) -> Option<&'static Shortcut> {
    SHORTCUTS.iter().find(|s| s.command == command)
}

/// A command's (first) shortcut as the menus show it, e.g. "Ctrl+O" or "R".
pub fn text(ctx: &egui::Context, command: Command) -> String {
    key_text(ctx, command, 0)
}

/// The shortcut of a command's `i`-th key as the menus show it.
pub fn key_text(ctx: &egui::Context, command: Command, i: usize) -> String {
    find(command).and_then(|s| s.keyboard_shortcut(i)).map(|s| ctx.format_shortcut(&s)).unwrap_or_default()
}

/// The shortcuts pressed this frame, in the table's order, each with the index of its key in the
/// row; first those that act while typing, then, unless a text field has the keyboard, the rest.
pub fn pressed(ctx: &egui::Context) -> Vec<(Command, usize)> {
    let mut out = Vec::new();
    let mut check = |typing: bool| {
        for s in SHORTCUTS.iter().filter(|s| s.while_typing == typing) {
            for (i, &key) in s.keys.iter().enumerate() {
                let hit = if s.modifiers.is_none() {
                    ctx.input(|input| input.key_pressed(key) && input.modifiers.is_none())
                } else {
                    ctx.input_mut(|input| input.consume_shortcut(&KeyboardShortcut::new(s.modifiers, key)))
                };
                if hit {
                    out.push((s.command, i));
                }
            }
        }
    };
    check(true);
    if !ctx.egui_wants_keyboard_input() {
        check(false);
    }
    out
}

/// The Help menu: the mouse controls, then the shortcuts.
pub fn help(ui: &mut egui::Ui) {
    egui::Grid::new("controls").num_columns(2).striped(true).show(ui, |ui| {
        let rows = MOUSE.iter().copied().chain(SHORTCUTS.iter().map(|s| (s.input, s.description)));
        for (input, description) in rows {
            ui.label(egui::RichText::new(input).strong());
            ui.label(description);
            ui.end_row();
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    /// How the table writes a key.
    fn written(key: Key) -> &'static str {
        match key {
            Key::Escape => "Esc",
            key => key.name(),
        }
    }

    #[test]
    fn inputs_name_their_keys_and_modifiers() {
        for s in &SHORTCUTS {
            let modifiers = if s.input.starts_with("Ctrl+Shift+") {
                Modifiers { shift: true, ..Modifiers::COMMAND }
            } else if s.input.starts_with("Ctrl+") {
                Modifiers::COMMAND
            } else {
                Modifiers::NONE
            };
            assert_eq!(modifiers, s.modifiers, "{}", s.input);
            let keys = s.input.trim_start_matches("Ctrl+").trim_start_matches("Shift+");
            let words: Vec<&str> = keys.split([' ']).filter(|w| *w != "or").collect();
            assert_eq!(words, s.keys.iter().map(|&k| written(k)).collect::<Vec<_>>(), "{}", s.input);
        }
        assert_eq!(find(Command::Views).map(|s| s.keys.len()), Some(vbrain::camera::View::ALL.len()));
    }

    #[test]
    fn each_command_has_one_row_and_each_key_one_meaning() {
        for s in &SHORTCUTS {
            assert_eq!(SHORTCUTS.iter().filter(|t| t.command == s.command).count(), 1, "{:?}", s.command);
            for &key in s.keys {
                let same = SHORTCUTS.iter().filter(|t| t.modifiers == s.modifiers && t.keys.contains(&key)).count();
                assert_eq!(same, 1, "{key:?}");
            }
        }
    }
}

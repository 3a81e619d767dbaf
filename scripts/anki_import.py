#!/usr/bin/env python3
"""Imports .apkg decks, in order, into a new empty Anki collection with Anki's own library (PyPI
package `anki`), as Anki's File > Import does, and prints what happened as JSON on one line:
per deck the notes added, updated and unchanged; then the collection's note and card counts, its
notes' fields and note types, its deck names, and which media files the fields name that the
collection lacks.

    python3 scripts/anki_import.py deck.apkg [more.apkg ...]
"""
import json
import os
import re
import sys
import tempfile

from anki.collection import Collection, ImportAnkiPackageOptions, ImportAnkiPackageRequest


def main():
    folder = tempfile.mkdtemp()
    col = Collection(os.path.join(folder, "collection.anki2"))
    imports = []
    for path in sys.argv[1:]:
        options = ImportAnkiPackageOptions(with_scheduling=True, update_notes=1, update_notetypes=1)
        log = col.import_anki_package(ImportAnkiPackageRequest(package_path=path, options=options)).log
        imports.append({"new": len(log.new), "updated": len(log.updated), "unchanged": len(log.duplicate)})
    media = set(os.listdir(col.media.dir()))
    notes, missing = [], set()
    for nid in col.find_notes(""):
        note = col.get_note(nid)
        fields = dict(note.items())
        notes.append({"type": note.note_type()["name"], "fields": fields, "tags": note.tags, "guid": note.guid})
        for value in fields.values():
            missing.update(name for name in re.findall(r'src="([^"]+)"', value) if name not in media)
    decks = sorted(d.name for d in col.decks.all_names_and_ids())
    print(json.dumps({"imports": imports, "notes": notes, "note_count": col.note_count(),
                      "card_count": col.card_count(), "decks": decks, "missing_media": sorted(missing)}))
    col.close()


if __name__ == "__main__":
    sys.exit(main())

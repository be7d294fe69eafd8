"""The evaluated flights under folders: one subfolder per flight holding
nadir_eval's outputs, either directly or in eval/ (a campaign's cell)."""
import os


def flight_files(folders, filename, tool):
    """[(flight name, path of its FILENAME)] under each folder, sorted by name.
    Exits naming the folder when one is not a folder."""
    found = []
    for folder in folders:
        if not os.path.isdir(folder):
            raise SystemExit(f"{tool}: error: {folder}: not a folder")
        for name in sorted(os.listdir(folder)):
            for sub in (filename, os.path.join("eval", filename)):
                path = os.path.join(folder, name, sub)
                if os.path.exists(path):
                    found.append((name, path))
                    break
    return found

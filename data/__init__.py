"""The built-in files (faces, marker sets, mappings, profiles, expressions), installed as ``toonface_data``.

Data only: ``common.data.data_path`` finds the folder with :mod:`importlib.resources`.
"""

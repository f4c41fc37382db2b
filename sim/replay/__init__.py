"""The replay of a run: ``recording`` watches a simulation (both worlds) from outside,
``page`` writes it with the viewer (``viewer.js``, built from ``viewer/src``) as one HTML file;
``cli`` is the ``--replay`` option of ``rdcd simulate``."""

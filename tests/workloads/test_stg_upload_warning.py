"""The dashboard upload shows the STG reader's warning (a first line counting the dummies) once."""

import pytest
from django.core.files.uploadedfile import SimpleUploadedFile
from django.urls import reverse

from apps.workloads.models import Application
from tests.workloads.test_stg_dummy_count import counting_dummies

pytestmark = pytest.mark.django_db


def test_upload_of_a_dummy_counting_stg_shows_the_warning(member):
    content = counting_dummies("sample00.stg").encode()
    response = member.post(reverse("workloads:applications"), {"file": SimpleUploadedFile("s.stg", content)})
    app = Application.objects.get()
    assert response.status_code == 302 and app.task_count == 10
    assert "warnings" not in app.graph.meta
    page = member.get(response["Location"]).content.decode()
    assert "message-warning" in page and "counts the two dummy tasks" in page
    assert "counts the two dummy tasks" not in member.get(response["Location"]).content.decode()  # shown once
